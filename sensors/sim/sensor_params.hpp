/// @file sensor_params.hpp
/// The optics + detector model of the simulated star camera (seed 004 chapter 3): how many
/// electrons a star of a given magnitude makes, and what noise the detector adds.
///
/// Signal (seed 004 eq. 3.4, written with physical units):
///   electrons = F0 * 10^(-0.4 V) * (pi D^2 / 4) * transmission * QE * t_exp
/// where F0 is the photon flux of a V = 0 star [photons / s / m^2]. The default F0 = 8.8e9
/// is the Johnson V zero point of Bessell, Castelli & Plez (1998, A&A 333, 231):
/// f_lambda(V=0) = 3.63e-11 W m^-2 nm^-1 at 545 nm, i.e. 1.0e8 photons s^-1 m^-2 nm^-1,
/// times the V passband width of 88 nm. The seed writes the zero point as 10^(28/2.5) in its
/// own units and folds QE and transmission into "FFSR" and the ADC gain g into the count;
/// here the gain is applied only at the ADC, so the electron count is gain-free.
///
/// Noise per pixel, in electrons (seed 004 eqs. 3.7-3.16): Poisson shot noise of the star,
/// the sky background (rate, eq. 3.8 style) and the dark current (eq. 3.8); Gaussian read
/// noise R (eq. 3.14); the ADC then divides by the gain [e-/ADU], adds the bias (black
/// level), rounds (quantisation noise Delta^2/12 in ADU^2 units = 1/12 ADU^2, eq. 3.12) and
/// clips to [0, 2^bits - 1]. A pixel's electron count is clipped at the full well first.
#pragma once
#include <cstdint>
#include <string>

#include "common/attitude.hpp"
#include "config/schema.hpp"
#include "sensors/camera/camera_model.hpp"

namespace mrpt::config {
class CConfigFileBase;
}

namespace st {

struct SensorParams {
  // --- optics and photometry (eq. 3.4) ---
  double aperture_diameter_m = 0.025;  ///< [m] entrance pupil diameter D
  double transmission = 0.8;           ///< optical transmission of the lens, 0..1
  double qe = 0.6;                     ///< quantum efficiency of the detector, 0..1
  double exposure_s = 0.1;             ///< [s] integration time t_exp (the longest, with max_smear_px)
  /// [px] > 0: each frame's exposure is the longest (up to exposure_s, down to min_exposure_s)
  /// whose smear at the frame's true body rate stays under this (sensors/detect/exposure.hpp,
  /// seed 004 sec. 4.2); 0: every frame exposes exposure_s.
  double max_smear_px = 0;
  double min_exposure_s = 1e-3;        ///< [s] the shortest exposure of the camera
  double v0_photon_flux = 8.8e9;       ///< [photons/s/m^2] F0, V = 0 star (see file comment)
  double psf_sigma_px = 1.0;           ///< [px] standard deviation of the Gaussian PSF

  // --- detector ---
  double sky_e_px_s = 5.0;             ///< [e-/px/s] diffuse sky + stray light background rate
  double dark_current_e_px_s = 20.0;   ///< [e-/px/s] dark current d (eq. 3.8)
  double read_noise_e = 10.0;          ///< [e-] RMS read noise R (eq. 3.14)
  double full_well_e = 20000.0;        ///< [e-] full-well capacity
  double gain_e_per_adu = 0;           ///< [e-/ADU]; 0 = full_well / 2^bits (eq. 3.9)
  int bit_depth = 8;                   ///< ADC bits, 8..16 (8 -> CV_8U image, else CV_16U)
  double bias_adu = 8.0;               ///< [ADU] black level added before quantisation

  // --- on-chip binning (a downlinked in-flight frame: Swarm's rows are binned 2x) ---
  /// Native pixels summed into one image pixel along columns (x) and rows (y): the PSF is
  /// psf_sigma_px / binning along each axis (psf_sigma_px is in native pixels), sky and dark
  /// add up over the summed pixels, read noise is added once (charge binned on chip). The
  /// scenario's camera states the image pixels' geometry (fy = fx * binning_x / binning_y).
  int binning_x = 1, binning_y = 1;

  // --- radiation hits (sensors/sim/radiation.hpp) ---
  /// [particles/cm^2/s] flux of charged particles through the detector (a low orbit outside
  /// the South Atlantic Anomaly: ~1-10; inside it, and in solar storms, 100x more: the
  /// [faults] saa_* keys); 0 = none
  double radiation_flux_cm2_s = 0;
  double pixel_pitch_um = 10;           ///< [um] native pixel pitch
  double radiation_depth_um = 10;       ///< [um] sensitive depth of the silicon
  /// [e-/um] mean charge a particle leaves along its path in silicon (a minimum-ionising one:
  /// ~80 e-/um; protons of tens of MeV several times more)
  double radiation_e_per_um = 80;
  /// lognormal sigma of a hit's charge about that mean: the energy spread of the particles
  double radiation_energy_spread = 0.7;

  // --- fixed hot pixels ---
  int hot_pixels = 0;                  ///< number of hot pixels (fixed positions per camera)
  double hot_pixel_e_px_s = 5000.0;    ///< [e-/px/s] dark current of a hot pixel
  uint64_t hot_pixel_seed = 12345;     ///< positions are a property of the camera, not a run

  /// The gain actually used [e-/ADU] (resolves 0 to eq. 3.9).
  double gain() const;
  /// Largest ADU value, 2^bits - 1.
  int maxAdu() const { return (1 << bit_depth) - 1; }
  /// Electrons collected from a star of visual magnitude `vmag` in one exposure (eq. 3.4).
  double starElectrons(double vmag) const;
  /// The exposure of a frame [s] taken at body (= camera) rate `omega` [rad/s] through `cam`.
  double exposureAt(const CameraModel& cam, const Vec3& omega) const;
  /// PSF sigma [image px] along x and y (psf_sigma_px over the binning).
  double psfSigmaX() const { return psf_sigma_px / binning_x; }
  double psfSigmaY() const { return psf_sigma_px / binning_y; }
  /// Mean electrons per pixel from sky + dark current in one exposure (no star, no hot pixel).
  double backgroundElectrons() const;
  /// Model mean and variance [ADU, ADU^2] of a pixel whose mean electron count is `lambda`,
  /// valid far from 0 and from saturation (seed 004 eq. 3.16 divided by gain^2, plus the
  /// 1/12 ADU^2 of quantisation, eq. 3.12).
  double modelMeanAdu(double lambda) const;
  double modelVarianceAdu(double lambda) const;

  /// Throws InputError naming `where` and the bad key if a value is out of range.
  void validate(const std::string& where) const;

  /// Reads the keys above from an .ini section (missing keys keep the defaults).
  /// aperture_diameter_mm is accepted in place of aperture_diameter_m.
  static SensorParams fromConfig(const mrpt::config::CConfigFileBase& cfg,
                                 const std::string& section);
  /// Strict read through sensorParamsSchema() (InputError names file, section and key).
  static SensorParams fromConfig(const IniReader& r, const std::string& section);
};

/// The keys of the simulated camera's [sensor] section, bound to SensorParams.
const SectionSchema<SensorParams>& sensorParamsSchema();

}  // namespace st

#include "sensors/sim/sensor_params.hpp"

#include <cmath>

#include "common/conventions.hpp"
#include "common/errors.hpp"
#include "sensors/detect/exposure.hpp"

namespace st {

double SensorParams::gain() const {
  // Eq. 3.9: the largest useful gain maps the full well onto the ADC range.
  return gain_e_per_adu > 0 ? gain_e_per_adu : full_well_e / std::ldexp(1.0, bit_depth);
}

double SensorParams::starElectrons(double vmag) const {
  // Seed 004 eq. 3.4 with physical units (see header): flux * area * throughput * time.
  const double area_m2 = 0.25 * kPi * aperture_diameter_m * aperture_diameter_m;
  return v0_photon_flux * std::pow(10.0, -0.4 * vmag) * area_m2 * transmission * qe * exposure_s;
}

double SensorParams::backgroundElectrons() const {
  // eq. 3.8 (D = d t) + background, over the native pixels binned into one
  return (sky_e_px_s + dark_current_e_px_s) * exposure_s * binning_x * binning_y;
}

double SensorParams::modelMeanAdu(double lambda) const { return bias_adu + lambda / gain(); }

double SensorParams::modelVarianceAdu(double lambda) const {
  const double g = gain();
  // Eq. 3.16 in ADU: Poisson (signal + dark + background) + read noise, plus eq. 3.12.
  return (lambda + read_noise_e * read_noise_e) / (g * g) + 1.0 / 12.0;
}

double SensorParams::exposureAt(const CameraModel& cam, const Vec3& omega) const {
  if (!(max_smear_px > 0)) return exposure_s;
  return exposureForRate(cam, omega, max_smear_px, min_exposure_s, exposure_s);
}

void SensorParams::validate(const std::string& where) const {
  auto bad = [&](const std::string& key, double v, const std::string& rule) {
    throw InputError(where + ": key '" + key + "' = " + std::to_string(v) + " " + rule);
  };
  if (!(aperture_diameter_m > 0)) bad("aperture_diameter_m", aperture_diameter_m, "must be > 0");
  if (!(transmission > 0 && transmission <= 1)) bad("transmission", transmission, "must be in (0, 1]");
  if (!(qe > 0 && qe <= 1)) bad("qe", qe, "must be in (0, 1]");
  if (!(exposure_s > 0)) bad("exposure_s", exposure_s, "must be > 0");
  if (!(max_smear_px >= 0)) bad("max_smear_px", max_smear_px, "must be >= 0 (0 = fixed exposure)");
  if (!(min_exposure_s > 0 && min_exposure_s <= exposure_s))
    bad("min_exposure_s", min_exposure_s, "must be in (0, exposure_s]");
  if (!(v0_photon_flux > 0)) bad("v0_photon_flux", v0_photon_flux, "must be > 0");
  if (!(psf_sigma_px >= 0.2)) bad("psf_sigma_px", psf_sigma_px, "must be >= 0.2");
  if (!(sky_e_px_s >= 0)) bad("sky_e_px_s", sky_e_px_s, "must be >= 0");
  if (!(dark_current_e_px_s >= 0)) bad("dark_current_e_px_s", dark_current_e_px_s, "must be >= 0");
  if (!(read_noise_e >= 0)) bad("read_noise_e", read_noise_e, "must be >= 0");
  if (!(full_well_e > 0)) bad("full_well_e", full_well_e, "must be > 0");
  if (!(gain_e_per_adu >= 0)) bad("gain_e_per_adu", gain_e_per_adu, "must be >= 0 (0 = eq. 3.9)");
  if (bit_depth < 8 || bit_depth > 16) bad("bit_depth", bit_depth, "must be in 8..16");
  if (!(bias_adu >= 0 && bias_adu < maxAdu())) bad("bias_adu", bias_adu, "must be in [0, 2^bits-1)");
  if (hot_pixels < 0) bad("hot_pixels", hot_pixels, "must be >= 0");
  if (binning_x < 1 || binning_x > 8) bad("binning_x", binning_x, "must be in 1..8");
  if (binning_y < 1 || binning_y > 8) bad("binning_y", binning_y, "must be in 1..8");
  if (!(radiation_flux_cm2_s >= 0 && radiation_flux_cm2_s <= 1e6))
    bad("radiation_flux_cm2_s", radiation_flux_cm2_s, "must be in [0, 1e6]");
  if (!(pixel_pitch_um > 0 && pixel_pitch_um <= 1000)) bad("pixel_pitch_um", pixel_pitch_um, "must be in (0, 1000]");
  if (!(radiation_depth_um > 0 && radiation_depth_um <= 1000))
    bad("radiation_depth_um", radiation_depth_um, "must be in (0, 1000]");
  if (!(radiation_e_per_um >= 0 && radiation_e_per_um <= 1e5))
    bad("radiation_e_per_um", radiation_e_per_um, "must be in [0, 1e5]");
  if (!(radiation_energy_spread >= 0 && radiation_energy_spread <= 3))
    bad("radiation_energy_spread", radiation_energy_spread, "must be in [0, 3]");
  if (!(hot_pixel_e_px_s >= 0)) bad("hot_pixel_e_px_s", hot_pixel_e_px_s, "must be >= 0");
}

const SectionSchema<SensorParams>& sensorParamsSchema() {
  using P = SensorParams;
  static const auto schema =
      SectionSchema<P>()
          .add("aperture_diameter_m", &P::aperture_diameter_m, "[m] entrance pupil diameter D")
          .alias("aperture_diameter_mm", &P::aperture_diameter_m, 1e-3,
                 "[mm] aperture_diameter_m in millimetres")
          .add("transmission", &P::transmission, "optical transmission of the lens, (0, 1]")
          .add("qe", &P::qe, "quantum efficiency of the detector, (0, 1]")
          .add("exposure_s", &P::exposure_s, "[s] integration time (the longest with max_smear_px)")
          .add("max_smear_px", &P::max_smear_px,
               "[px] > 0: exposure per frame from the true rate, smear under this; 0 = fixed")
          .add("min_exposure_s", &P::min_exposure_s, "[s] shortest exposure (max_smear_px)")
          .add("v0_photon_flux", &P::v0_photon_flux, "[photons/s/m^2] flux of a V = 0 star")
          .add("psf_sigma_px", &P::psf_sigma_px, "[px] sigma of the Gaussian PSF, >= 0.2")
          .add("sky_e_px_s", &P::sky_e_px_s, "[e-/px/s] sky + stray light background rate")
          .add("dark_current_e_px_s", &P::dark_current_e_px_s, "[e-/px/s] dark current")
          .add("read_noise_e", &P::read_noise_e, "[e-] RMS read noise")
          .add("full_well_e", &P::full_well_e, "[e-] full-well capacity")
          .add("gain_e_per_adu", &P::gain_e_per_adu, "[e-/ADU] ADC gain; 0 = full_well / 2^bits")
          .add("bit_depth", &P::bit_depth, "ADC bits, 8..16")
          .add("bias_adu", &P::bias_adu, "[ADU] black level")
          .add("binning_x", &P::binning_x, "native pixels binned per image column, 1..8")
          .add("binning_y", &P::binning_y, "native pixels binned per image row, 1..8 (PSF / binning)")
          .add("radiation_flux_cm2_s", &P::radiation_flux_cm2_s,
               "[particles/cm^2/s] charged-particle flux through the detector; 0 = none")
          .add("pixel_pitch_um", &P::pixel_pitch_um, "[um] native pixel pitch (hit rate, track length)")
          .add("radiation_depth_um", &P::radiation_depth_um, "[um] sensitive depth of the silicon")
          .add("radiation_e_per_um", &P::radiation_e_per_um, "[e-/um] mean charge per um of a hit's path")
          .add("radiation_energy_spread", &P::radiation_energy_spread,
               "lognormal sigma of a hit's charge")
          .add("hot_pixels", &P::hot_pixels, "number of hot pixels")
          .add("hot_pixel_e_px_s", &P::hot_pixel_e_px_s, "[e-/px/s] dark current of a hot pixel")
          .add("hot_pixel_seed", &P::hot_pixel_seed, "seed of the hot pixel positions");
  return schema;
}

SensorParams SensorParams::fromConfig(const mrpt::config::CConfigFileBase& cfg,
                                      const std::string& section) {
  return fromConfig(IniReader{cfg, ""}, section);
}

SensorParams SensorParams::fromConfig(const IniReader& r, const std::string& section) {
  SensorParams p;
  sensorParamsSchema().read(r, section, p);
  // Both units at once would be two answers to one question.
  if (r.has(section, "aperture_diameter_mm") && r.has(section, "aperture_diameter_m"))
    throw InputError(r.whereKey(section, "aperture_diameter_mm") +
                     ": give either aperture_diameter_m or aperture_diameter_mm");
  p.validate(r.where(section));
  return p;
}

}  // namespace st

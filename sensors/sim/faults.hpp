/// @file faults.hpp
/// Faults and clutter of the simulated camera, each switched on from the scenario's
/// [faults] section (all off by default):
///  - false stars: planet-like point sources fixed in the inertial frame, not in the catalog
///    (seed 000's "spikes ... due to planets"); rendered with the optics' PSF, absent from
///    the ground truth;
///  - spikes: cosmic-ray / radiation hits, a Poisson number per frame, each a sharp track of
///    a few pixels (no PSF) carrying a random charge (seed 000's "electronic noise");
///  - a bright extended object: a wide Gaussian blob fixed in the inertial frame;
///  - missing stars: a stable fraction of catalog stars is not rendered (and not in truth);
///  - a blinding source (Sun/Earth/Moon stray light): extra background
///    rate * 1 / (1 + (r / radius)^2) around a centre that may lie outside the frame,
///    during [blinding_start_s, blinding_end_s];
///  - dropped frames: each frame lost with a probability, and whole dropout intervals (a
///    camera that stops and restarts);
///  - frozen images: during an interval the camera repeats the last image read before it (a
///    stuck readout) with fresh timestamps, while the truth moves on;
///  - camera clock jumps: from a time on, the camera stamps its frames dt later (dt > 0) or
///    earlier (dt < 0); jumps add up. `simulate` stamps the ground truth with the true clock
///    (the truth is no camera's); the live simulated camera still stamps its truth with its
///    own clock;
///  - a South Atlantic Anomaly pass: the radiation hits' flux (sensors/sim/radiation.hpp)
///    multiplied during an interval;
///  - gyro faults during [gyro_fault_start_s, gyro_fault_end_s): one axis stuck at its last
///    reading, and/or one axis with extra white noise; spikes: single samples with a large
///    error on one random axis, a Poisson number per second over the whole run.
///
/// .ini keys:
///   false_stars (count), false_star_mag_min, false_star_mag_max
///   spikes_per_frame (Poisson mean), spike_e_min, spike_e_max [e-], spike_length_max_px
///   extended_objects (count), extended_mag, extended_sigma_px
///   missing_star_fraction (0..1)
///   blinding_e_px_s (peak rate; 0 = off), blinding_center_px = x y, blinding_radius_px,
///   blinding_start_s, blinding_end_s
///   drop_frame_probability (0..1), dropout_s = t0 t1 [t0 t1 ...] (frames with t in [t0, t1)
///   are not delivered)
///   frozen_s = t0 t1 [...], camera_time_jump_s = t dt [t dt ...]
///   gyro_stuck_axis, gyro_noisy_axis (0 1 2 = x y z, -1 = none), gyro_noise_deg_s,
///   gyro_fault_start_s, gyro_fault_end_s, gyro_spikes_per_s, gyro_spike_deg_s
///   saa_start_s, saa_end_s, saa_flux_factor (radiation burst: [sensor] radiation_flux_cm2_s
///   times the factor during the interval)
#pragma once
#include <cstdint>
#include <opencv2/core.hpp>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "common/attitude.hpp"
#include "config/schema.hpp"
#include "sensors/sim/star_renderer.hpp"

namespace mrpt::config {
class CConfigFileBase;
}

namespace st {

class MotionProfile;

struct FaultParams {
  int false_stars = 0;
  double false_star_mag_min = 1.0, false_star_mag_max = 4.0;
  double spikes_per_frame = 0;
  double spike_e_min = 2000, spike_e_max = 30000;  ///< [e-] charge of one hit
  double spike_length_max_px = 8;
  int extended_objects = 0;
  double extended_mag = 0.0;
  double extended_sigma_px = 12;
  double missing_star_fraction = 0;
  double blinding_e_px_s = 0;
  Vec2 blinding_center_px = Vec2(-50, -50);
  double blinding_radius_px = 150;
  double blinding_start_s = 0, blinding_end_s = 1e300;
  double drop_frame_probability = 0;
  std::vector<std::pair<double, double>> dropouts;  ///< [t0, t1) in seconds from the start
  std::vector<std::pair<double, double>> frozen;    ///< [t0, t1): the image of before t0
  std::vector<std::pair<double, double>> camera_time_jumps;  ///< (t, dt): stamps + dt from t
  int gyro_stuck_axis = -1, gyro_noisy_axis = -1;  ///< 0 1 2 = x y z; -1 = none
  double gyro_noise_deg_s = 0;                      ///< [deg/s] 1 sigma per sample, noisy axis
  double gyro_fault_start_s = 0, gyro_fault_end_s = 1e300;
  double gyro_spikes_per_s = 0;                     ///< Poisson rate of single-sample spikes
  double gyro_spike_deg_s = 5;                      ///< [deg/s] size of a spike (random sign)
  /// A South Atlantic Anomaly pass (or a solar particle event): the radiation flux
  /// ([sensor] radiation_flux_cm2_s) times saa_flux_factor during [saa_start_s, saa_end_s).
  double saa_start_s = 0, saa_end_s = 0;
  double saa_flux_factor = 100;

  static FaultParams fromConfig(const mrpt::config::CConfigFileBase& cfg,
                                const std::string& section);
  /// Strict read through faultParamsSchema() (InputError names file, section and key).
  static FaultParams fromConfig(const IniReader& r, const std::string& section);
  void validate(const std::string& where) const;
};

/// The keys of the [faults] section, bound to FaultParams.
const SectionSchema<FaultParams>& faultParamsSchema();

/// Places the false stars and extended objects of a run: each at a random pixel of the
/// frame at a random time of the run, turned into an inertial direction, so that they are
/// met along the trajectory. Deterministic for a seed.
std::vector<ExtraSource> placeFalseSources(const FaultParams& f, const CameraModel& cam,
                                           const MotionProfile& motion, double duration_s,
                                           double psf_sigma_px, uint64_t seed);

/// Adds this frame's cosmic-ray hits to a mean-electron image; returns how many.
int addSpikes(cv::Mat& electrons, const FaultParams& f, std::mt19937_64& rng);

/// The radiation flux's factor at time t [s]: saa_flux_factor inside the SAA interval, else 1.
double saaFactor(const FaultParams& f, double t);

/// Adds the blinding glow (mean electrons) for a frame at time t [s] with exposure T [s].
void addBlinding(cv::Mat& electrons, const FaultParams& f, double t, double exposure_s);

/// Whether frame `index` at time t [s] is dropped (deterministic for a seed).
bool isFrameDropped(const FaultParams& f, uint64_t seed, int index, double t);

/// The frame whose image frame k (at t [s]) shows: k, or for a frozen frame the last frame
/// before its frozen interval (0 if the interval starts before the first frame).
int frozenImageSource(const FaultParams& f, int k, double t, double frame_rate_hz);

/// The camera's clock at true time t [s]: t plus every jump at or before t.
double cameraClock(const FaultParams& f, double t);

/// The gyro's faults on sample `index` (time t [s], measured mean rate in rad/s); `held` is
/// the stuck axis' last good reading, kept by the caller across samples. Deterministic for a
/// seed.
void applyGyroFaults(Vec3& rate, Vec3& held, const FaultParams& f, uint64_t seed, int index,
                     double t, double rate_hz);

}  // namespace st

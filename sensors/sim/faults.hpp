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
///  - dropped frames: each frame lost with a probability, and whole dropout intervals.
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

/// Adds the blinding glow (mean electrons) for a frame at time t [s] with exposure T [s].
void addBlinding(cv::Mat& electrons, const FaultParams& f, double t, double exposure_s);

/// Whether frame `index` at time t [s] is dropped (deterministic for a seed).
bool isFrameDropped(const FaultParams& f, uint64_t seed, int index, double t);

}  // namespace st

/// @file rawlog_writer.hpp
/// Plays a scenario offline into an observation-only, gz-compressed rawlog (the format of
/// sim_observations.hpp): GYRO, VELOCITY (an orbit's), CAMERA and GROUND_TRUTH on one clock,
/// in timestamp order (at equal timestamps: GYRO, VELOCITY, CAMERA, GROUND_TRUTH). Images are stored as
/// external PNG files in `<rawlog stem>_Images/` beside the rawlog (MRPT's convention, so
/// RawLogViewer finds them), or inline.
#pragma once
#include <cstddef>
#include <memory>
#include <optional>
#include <string>

#include "sensors/sim/scenario.hpp"

namespace st {

struct SimulateOptions {
  std::optional<uint64_t> seed;  ///< overrides the scenario's seed
  std::optional<int> frames;     ///< limits the run to this many frames
  bool external_images = true;
  bool progress = true;          ///< progress bar on stderr
  /// Optional star source (tests); default: the scenario's database / catalog.
  std::shared_ptr<const StarSource> stars;
};

struct SimulateSummary {
  int frames = 0;          ///< frame slots (GROUND_TRUTH objects)
  int frames_dropped = 0;  ///< of which without a CAMERA observation
  int gyro_samples = 0;
  int velocity_samples = 0;  ///< VELOCITY observations (a scenario with an orbit)
  std::size_t objects = 0; ///< observations written
  std::string images_dir;  ///< empty when images are inline
  uint64_t seed = 0;
};

/// Throws InputError if the rawlog or the images folder cannot be written.
SimulateSummary simulateToRawlog(const Scenario& scenario, const std::string& rawlog_path,
                                 const SimulateOptions& opts = {});

/// `<dir>/<stem>_Images` for a rawlog path `<dir>/<stem>.rawlog`.
std::string externalImagesDir(const std::string& rawlog_path);

}  // namespace st

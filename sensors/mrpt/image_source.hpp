/// @file image_source.hpp
/// What an image source of CStarTrackerSensor can tell beyond its frames. The source is any
/// MRPT sensor the factory knows by class name (a CCameraSensor grabber, the simulated star
/// camera of the separate simulator plugin, ...); a source that also implements this
/// interface supplies the defaults the sensor's own keys and camera file leave open (a
/// simulated camera knows its optics, noise and epoch; a real grabber knows none of them).
#pragma once
#include <mrpt/poses/CPose3D.h>

#include <optional>

#include "sensors/camera/camera_model.hpp"

namespace st {

/// The simulator plugin's star camera (sensors/sim/simulated_sensors.hpp), created by name.
inline constexpr const char* kSimulatedCameraClass = "CSimulatedStarCamera";

struct ImageSourceFacts {
  std::optional<CameraModel> camera;
  std::optional<double> exposure_s;
  std::optional<double> gain_e_per_adu;
  std::optional<double> read_noise_adu;
  std::optional<double> epoch_jyear;  ///< of the sky it shows
  /// Its mounting on the body (body from camera), where the source knows it: a simulated
  /// scenario's camera head.
  std::optional<mrpt::poses::CPose3D> mount;
};

/// A sensor whose data ends (a scenario played to its end, a folder of frames): the live
/// app stops when every sensor has finished or failed, instead of waiting for Ctrl-C.
class FiniteSensor {
 public:
  virtual ~FiniteSensor() = default;
  /// True when the sensor will deliver nothing more.
  virtual bool finished() const = 0;
};

class StarImageSource : public FiniteSensor {
 public:
  /// Available after loadConfig(); throws InputError naming the file for a bad one.
  virtual ImageSourceFacts facts() const = 0;
};

}  // namespace st

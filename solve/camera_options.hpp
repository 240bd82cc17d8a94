/// @file camera_options.hpp
/// The camera options shared by every command that needs a camera: `--camera FILE`
/// (OpenCV YAML/XML, or an MRPT .ini with `--camera-section`) or `--fov-deg`, the HORIZONTAL
/// field of view (of the image width; the same meaning in every command), with the image
/// size (principal point at the centre).
#pragma once
#include <optional>
#include <string>

#include "sensors/camera/camera_model.hpp"

namespace st::solve {

struct CameraOptions {
  std::string camera_file;
  std::string camera_section = "CAMERA";
  double fov_deg = 0;

  /// True when the user gave a camera file or a FOV.
  bool given() const { return !camera_file.empty() || fov_deg > 0; }
  /// The camera for an image of the given size (throws InputError on a bad file or when
  /// neither option is given, or the camera's size does not match the image).
  CameraModel resolve(int width, int height) const;
};

}  // namespace st::solve

/// @file camera_options.hpp
/// The camera options shared by every command that needs a camera: `--camera FILE`
/// (OpenCV YAML/XML, or an MRPT .ini with `--camera-section`) or `--fov-deg`, the HORIZONTAL
/// field of view (of the image width; the same meaning in every command), with the image
/// size (principal point at the centre).
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "sensors/camera/camera_model.hpp"

namespace st::solve {

struct CameraOptions {
  std::string camera_file;
  std::string camera_section = "CAMERA";
  double fov_deg = 0;
  /// A pixel's height over its width on the sky, for an image without a camera file (2 for
  /// rows binned 2x on board); 0 = not given (square pixels, or the camera file's).
  double pixel_aspect = 0;
  /// On-board binning {columns, rows} (e.g. {1, 2}): the pixel aspect rows / columns; empty =
  /// not given. The option_prefix names both in messages.
  std::vector<int> binning;

  /// True when the user gave a camera file or a FOV.
  bool given() const { return !camera_file.empty() || fov_deg > 0; }
  /// The pixel aspect of a camera built from a FOV (1 when neither --pixel-aspect nor
  /// --binning); InputError when both are given, or either beside a camera file (whose
  /// fx and fy state the pixels' geometry), or a value is out of range.
  double pixelAspect(const std::string& option_prefix = "--") const;
  /// The camera for an image of the given size (throws InputError on a bad file or when
  /// neither option is given, or the camera's size does not match the image).
  CameraModel resolve(int width, int height) const;
};

}  // namespace st::solve

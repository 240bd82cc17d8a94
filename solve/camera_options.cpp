#include "solve/camera_options.hpp"

#include "common/conventions.hpp"
#include "common/errors.hpp"

namespace st::solve {

CameraModel CameraOptions::resolve(int width, int height) const {
  if (!camera_file.empty()) {
    CameraModel cam = CameraModel::loadFile(camera_file, camera_section);
    if ((width > 0 && cam.width() != width) || (height > 0 && cam.height() != height))
      throw InputError(camera_file + ": camera is " + std::to_string(cam.width()) + "x" +
                       std::to_string(cam.height()) + " but the image is " +
                       std::to_string(width) + "x" + std::to_string(height));
    return cam;
  }
  if (fov_deg > 0) return CameraModel::fromFov(width, height, deg2rad(fov_deg));
  throw InputError("no camera given: use --camera FILE or --fov-deg X");
}

}  // namespace st::solve

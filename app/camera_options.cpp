#include "app/camera_options.hpp"

#include "app/cli/validators.hpp"

#include "common/conventions.hpp"
#include "common/errors.hpp"

namespace st::app {

void CameraOptions::addTo(CLI::App& cmd) {
  auto* cam = cmd.add_option("--camera", camera_file,
                             "Camera file: OpenCV YAML/XML (camera_matrix, distortion_coefficients, "
                             "image_width, image_height) or MRPT .ini (see --camera-section)");
  cmd.add_option("--camera-section", camera_section, "Section of an .ini camera file")
      ->capture_default_str();
  cmd.add_option("--fov-deg", fov_deg,
                 "Horizontal field of view [deg]: the image width's angle (principal point at "
                 "the centre)")
      ->check(cli::Number(0.1, 179))
      ->excludes(cam);
}

CameraModel CameraOptions::resolve(int width, int height) const {
  if (!camera_file.empty()) {
    const bool ini = camera_file.size() > 4 &&
                     camera_file.compare(camera_file.size() - 4, 4, ".ini") == 0;
    CameraModel cam = ini ? CameraModel::loadIniFile(camera_file, camera_section)
                          : CameraModel::loadYaml(camera_file);
    if ((width > 0 && cam.width() != width) || (height > 0 && cam.height() != height))
      throw InputError(camera_file + ": camera is " + std::to_string(cam.width()) + "x" +
                       std::to_string(cam.height()) + " but the image is " +
                       std::to_string(width) + "x" + std::to_string(height));
    return cam;
  }
  if (fov_deg > 0) return CameraModel::fromFov(width, height, deg2rad(fov_deg));
  throw InputError("no camera given: use --camera FILE or --fov-deg X");
}

}  // namespace st::app

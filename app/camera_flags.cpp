// The camera flags every command that needs a camera shares (solve/camera_options.hpp).
#include "app/camera_flags.hpp"

#include "app/cli/validators.hpp"

namespace st::app {

void addCameraFlags(CLI::App& cmd, solve::CameraOptions& o) {
  auto* cam = cmd.add_option("--camera", o.camera_file,
                             "Camera file: OpenCV YAML/XML (camera_matrix, distortion_coefficients, "
                             "image_width, image_height) or MRPT .ini (see --camera-section)");
  cmd.add_option("--camera-section", o.camera_section, "Section of an .ini camera file")
      ->capture_default_str();
  cmd.add_option("--fov-deg", o.fov_deg,
                 "Horizontal field of view [deg]: the image width's angle (principal point at "
                 "the centre)")
      ->check(cli::Number(0.1, 179))
      ->excludes(cam);
  auto* aspect = cmd.add_option("--pixel-aspect", o.pixel_aspect,
                 "A pixel's height over its width on the sky, for an image without a camera "
                 "file: 2 for rows binned 2x on board (fy = fx / A; the FOV search and the fit "
                 "keep fx and fy apart)")
      ->check(cli::Number(kMinPixelAspect, kMaxPixelAspect))
      ->excludes(cam);
  cmd.add_option("--binning", o.binning,
                 "On-board binning BX BY (columns, rows): the same as --pixel-aspect BY/BX")
      ->expected(2)
      ->check(CLI::Range(1, 8))
      ->excludes(cam)
      ->excludes(aspect);
}

}  // namespace st::app

#include "solve/camera_options.hpp"

#include "common/conventions.hpp"
#include "common/errors.hpp"

namespace st::solve {

double CameraOptions::pixelAspect(const std::string& option_prefix) const {
  const std::string pa = option_prefix + (option_prefix.empty() ? "pixel_aspect" : "pixel-aspect");
  const std::string bin = option_prefix + "binning";
  if (pixel_aspect != 0 && !binning.empty())
    throw InputError(pa + " and " + bin + " say the same thing: give one");
  if ((pixel_aspect != 0 || !binning.empty()) && !camera_file.empty())
    throw InputError((pixel_aspect != 0 ? pa : bin) + ": the camera file " + camera_file +
                     " states the pixels' geometry (fx, fy); give one or the other");
  if (!binning.empty()) {
    if (binning.size() != 2 || binning[0] < 1 || binning[1] < 1 || binning[0] > 8 || binning[1] > 8)
      throw InputError(bin + " needs two whole numbers BX BY from 1 to 8 (columns, rows binned)");
    return static_cast<double>(binning[1]) / binning[0];
  }
  if (pixel_aspect == 0) return 1.0;
  if (!(pixel_aspect >= kMinPixelAspect && pixel_aspect <= kMaxPixelAspect))
    throw InputError(pa + " " + std::to_string(pixel_aspect) + ": a pixel's height over its "
                     "width on the sky, from 0.125 to 8");
  return pixel_aspect;
}

CameraModel CameraOptions::resolve(int width, int height) const {
  pixelAspect();  // a camera file beside --pixel-aspect is refused, not ignored
  if (!camera_file.empty()) {
    CameraModel cam = CameraModel::loadFile(camera_file, camera_section);
    if ((width > 0 && cam.width() != width) || (height > 0 && cam.height() != height))
      throw InputError(camera_file + ": camera is " + std::to_string(cam.width()) + "x" +
                       std::to_string(cam.height()) + " but the image is " +
                       std::to_string(width) + "x" + std::to_string(height));
    return cam;
  }
  if (fov_deg > 0)
    return CameraModel::fromFov(width, height, deg2rad(fov_deg), pixelAspect());
  throw InputError("no camera given: use --camera FILE or --fov-deg X");
}

}  // namespace st::solve

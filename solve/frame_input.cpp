#include "solve/frame_input.hpp"

#include <chrono>

#include "imageio/image_file.hpp"
#include "solve/solve_options.hpp"
#include "solve/star_list.hpp"
#include "common/errors.hpp"
#include "sensors/detect/star_detector.hpp"

namespace st::solve {
namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

FrameInput fromStarList(const SolveOptions& o) {
  const auto t0 = Clock::now();
  StarList list = loadStarList(o.input);
  FrameInput in;
  in.star_list = true;
  // The flags win over the file's header: they are what the user just said.
  in.width = o.width > 0 ? o.width : list.width;
  in.height = o.height > 0 ? o.height : list.height;
  if (in.width <= 0 || in.height <= 0)
    throw InputError(o.input + ": a star list needs the image size: give --width and --height "
                               "(or IMAGEW/IMAGEH in a FITS table's header)");
  for (const Centroid& c : list.stars)
    if (c.px.x() < -0.5 || c.px.y() < -0.5 || c.px.x() > in.width - 0.5 ||
        c.px.y() > in.height - 0.5)
      throw InputError(o.input + ": star at (" + std::to_string(c.px.x()) + ", " +
                       std::to_string(c.px.y()) + ") lies outside the " +
                       std::to_string(in.width) + "x" + std::to_string(in.height) + " image");
  in.stars = std::move(list.stars);
  in.epoch_jyear = list.epoch_jyear;
  in.epoch_source = list.epoch_source;
  in.load_ms = msSince(t0);
  return in;
}

}  // namespace

FrameInput loadFrameInput(const SolveOptions& o, double pixel_aspect) {
  if (isStarList(o.input)) return fromStarList(o);
  if (o.width > 0 || o.height > 0)
    throw InputError("--width/--height: only for a star list; " + o.input +
                     " is an image and has its own size");
  const auto t0 = Clock::now();
  imageio::LoadedImage img = imageio::loadImage(o.input);
  FrameInput in = frameInputFromImage(img.image, o, o.input, pixel_aspect);
  in.load_ms = msSince(t0) - in.detect_ms;
  in.epoch_jyear = img.epoch_jyear;
  in.epoch_source = img.epoch_source;
  return in;
}

FrameInput frameInputFromImage(const cv::Mat& image, const SolveOptions& o, const std::string& name,
                               double pixel_aspect) {
  FrameInput in;
  in.width = image.cols;
  in.height = image.rows;
  const auto t0 = Clock::now();
  DetectorOptions dopts;
  dopts.pixel_aspect = pixel_aspect;
  if (!o.dark_frame.empty()) {
    const cv::Mat& d = o.dark_frame;
    if (d.size() != image.size() || d.depth() != image.depth())
      throw InputError("--dark " + o.dark + ": " + std::to_string(d.cols) + "x" +
                       std::to_string(d.rows) + " " + cv::typeToString(d.type()) +
                       " differs from the image " + name + " (" + std::to_string(image.cols) +
                       "x" + std::to_string(image.rows) + " " + cv::typeToString(image.type()) +
                       ")");
    dopts.dark_frame = d;
  }
  DetectionResult det = detectStars(image, dopts);
  in.detect_ms = msSince(t0);
  in.stars = std::move(det.stars);
  in.detection_reason = det.reason;
  in.psf_width_x = det.psf_width_x;
  in.psf_width_y = det.psf_width_y;
  in.hits = det.hits;
  in.pixel_aspect = pixel_aspect;
  in.rejected = std::move(det.rejected_blobs);
  in.image = image;  // a header: the caller's pixels, or the loaded image's
  return in;
}

}  // namespace st::solve

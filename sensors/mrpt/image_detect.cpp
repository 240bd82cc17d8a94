#include "sensors/mrpt/image_detect.hpp"

#include <mrpt/img/CImage.h>

#include <exception>
#include <string>

namespace st {

DetectionResult detect(StarDetector& detector, const mrpt::img::CImage& image) {
  try {
    return detector.detect(image.asCvMatRef());
  } catch (const std::exception& e) {
    DetectionResult r;
    r.reason = std::string("cannot read image: ") + e.what();
    return r;
  }
}

void centroidWindows(StarDetector& detector, const mrpt::img::CImage& image,
                     const std::vector<PredictedStar>& predicted, std::vector<WindowResult>& out) {
  try {
    detector.centroidWindows(image.asCvMatRef(), predicted, out);
  } catch (const std::exception& e) {
    out.assign(predicted.size(), WindowResult{});
    for (auto& w : out) w.reason = std::string("cannot read image: ") + e.what();
  }
}

DetectionResult detectStars(const mrpt::img::CImage& image, const DetectorOptions& opts) {
  StarDetector d(opts);
  return detect(d, image);
}

std::vector<WindowResult> centroidWindows(const mrpt::img::CImage& image,
                                          const std::vector<PredictedStar>& predicted,
                                          const DetectorOptions& opts) {
  StarDetector d(opts);
  std::vector<WindowResult> out;
  centroidWindows(d, image, predicted, out);
  return out;
}

}  // namespace st

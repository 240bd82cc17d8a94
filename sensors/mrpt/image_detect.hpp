/// @file image_detect.hpp
/// The detector on MRPT's images (CObservationImage::image): read through asCvMatRef(), no
/// copy. An image MRPT cannot read (an external file gone) is a bad image: a result with a
/// reason, not a throw. The detector itself (sensors/detect/) knows only cv::Mat.
#pragma once
#include <vector>

#include "sensors/detect/star_detector.hpp"

namespace mrpt::img {
class CImage;
}

namespace st {

DetectionResult detect(StarDetector& detector, const mrpt::img::CImage& image);
void centroidWindows(StarDetector& detector, const mrpt::img::CImage& image,
                     const std::vector<PredictedStar>& predicted, std::vector<WindowResult>& out);

/// One detector per call (StarDetector's convenience wrappers), on an MRPT image.
DetectionResult detectStars(const mrpt::img::CImage& image, const DetectorOptions& opts = {});
std::vector<WindowResult> centroidWindows(const mrpt::img::CImage& image,
                                          const std::vector<PredictedStar>& predicted,
                                          const DetectorOptions& opts = {});

}  // namespace st

/// @file annotate.hpp
/// A labelled picture of a solved frame: the image stretched to 8 bits, every detected blob
/// circled, every identified star circled in green with its catalog number, and a caption.
#pragma once
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "common/attitude.hpp"

namespace st::solve {

struct LabelledStar {
  Vec2 px;
  std::string label;
};

/// Returns a BGR 8-bit picture (percentile stretch of the grey input, 8- or 16-bit).
cv::Mat annotateFrame(const cv::Mat& grey, const std::vector<Vec2>& detections,
                      const std::vector<LabelledStar>& identified,
                      const std::vector<std::string>& caption);

/// annotateFrame + write as PNG; throws InputError naming the path when it cannot be written.
void writeAnnotatedFrame(const std::string& path, const cv::Mat& grey,
                         const std::vector<Vec2>& detections,
                         const std::vector<LabelledStar>& identified,
                         const std::vector<std::string>& caption);

}  // namespace st::solve

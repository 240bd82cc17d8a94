/// @file annotate.hpp
/// A labelled picture of a frame, solved or not: the image stretched to 8 bits (rows repeated
/// for binned pixels, so the sky keeps its shape), every blob marked by what detection made
/// of it (star, radiation hit, diffuse, rejected), every identified star circled in green
/// with its catalog number, and a caption (the solution, or why the solve stopped).
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

/// What detection made of a blob: a star (kept), a radiation hit (kept, ranked last), a
/// diffuse or elongated one (kept, ranked after the stars), or rejected (dropped).
enum class BlobKind { kStar, kHit, kDiffuse, kRejected };
struct MarkedBlob {
  Vec2 px;
  BlobKind kind;
};

/// Returns a BGR 8-bit picture (percentile stretch of the grey input, 8- or 16-bit). A
/// `pixel_aspect` of 2 or more (rows binned) repeats each row that many times (rounded).
cv::Mat annotateFrame(const cv::Mat& grey, const std::vector<MarkedBlob>& blobs,
                      const std::vector<LabelledStar>& identified,
                      const std::vector<std::string>& caption, double pixel_aspect = 1);

/// annotateFrame + write as PNG; throws InputError naming the path when it cannot be written.
void writeAnnotatedFrame(const std::string& path, const cv::Mat& grey,
                         const std::vector<MarkedBlob>& blobs,
                         const std::vector<LabelledStar>& identified,
                         const std::vector<std::string>& caption, double pixel_aspect = 1);

}  // namespace st::solve

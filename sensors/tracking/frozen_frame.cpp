#include "sensors/tracking/frozen_frame.hpp"

#include <cstdio>

namespace st {

namespace {

/// FNV-1a over the pixel bytes, row by row (a view may have gaps between rows).
uint64_t imageHash(const cv::Mat& m) {
  uint64_t h = 1469598103934665603ull;
  const std::size_t row_bytes = static_cast<std::size_t>(m.cols) * m.elemSize();
  for (int r = 0; r < m.rows; ++r) {
    const uint8_t* p = m.ptr<uint8_t>(r);
    for (std::size_t i = 0; i < row_bytes; ++i) h = (h ^ p[i]) * 1099511628211ull;
  }
  return h;
}

}  // namespace

std::optional<double> FrozenFrameCheck::repeats(const cv::Mat& image, double t_s) {
  const uint64_t hash = imageHash(image);
  if (last_t_ && hash == last_hash_ && image.size() == last_size_ && image.type() == last_type_)
    return last_t_;
  last_hash_ = hash;
  last_size_ = image.size();
  last_type_ = image.type();
  last_t_ = t_s;
  return std::nullopt;
}

FrameResult frozenFrameResult(double seen_t_s) {
  FrameResult r;
  char b[96];
  std::snprintf(b, sizeof b, "frozen image: identical to the frame at t = %.6f s", seen_t_s);
  r.failure = FrameFailure::kFrozenImage;
  r.detail = b;
  return r;
}

}  // namespace st

#include "sensors/tracking/frozen_frame.hpp"

#include <opencv2/imgproc.hpp>

#include "sensors/tracking/star_tracker.hpp"

#include <cstdio>
#include <cstring>

namespace st {

namespace {

/// FNV-1a style over the pixel bytes, row by row (a view may have gaps between rows), 8
/// bytes at a time in four independent lanes: the multiply chains run side by side (~25x
/// faster than byte by byte, which cost more than tracking a frame).
uint64_t imageHash(const cv::Mat& m) {
  constexpr uint64_t kPrime = 1099511628211ull;
  uint64_t lane[4] = {1469598103934665603ull, 0x9e3779b97f4a7c15ull, 0xc2b2ae3d27d4eb4full,
                      0x165667b19e3779f9ull};
  const std::size_t row_bytes = static_cast<std::size_t>(m.cols) * m.elemSize();
  for (int r = 0; r < m.rows; ++r) {
    const uint8_t* p = m.ptr<uint8_t>(r);
    std::size_t i = 0;
    for (; i + 32 <= row_bytes; i += 32)
      for (int j = 0; j < 4; ++j) {
        uint64_t w;
        std::memcpy(&w, p + i + 8 * j, 8);
        lane[j] = (lane[j] ^ w) * kPrime;
      }
    for (; i < row_bytes; ++i) lane[0] = (lane[0] ^ p[i]) * kPrime;
  }
  uint64_t h = lane[0];
  for (int j = 1; j < 4; ++j) h = (h ^ (lane[j] + (h << 6) + (h >> 2))) * kPrime;
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

FrameResult processFrame(StarTracker& tracker, FrozenFrameCheck& frozen, const cv::Mat& image,
                         double t_s, const FrameInputs& in) {
  cv::Mat grey = image;
  if (image.channels() == 3 || image.channels() == 4)
    cv::cvtColor(image, grey, image.channels() == 3 ? cv::COLOR_BGR2GRAY : cv::COLOR_BGRA2GRAY);
  if (const std::optional<double> seen = frozen.repeats(grey, t_s)) return frozenFrameResult(*seen);
  return tracker.process(grey, t_s, in);
}

}  // namespace st

/// @file frozen_frame.hpp
/// A camera that repeats its readout (a frozen image): the same pixels again at a new time
/// would give the old attitude stamped with the new time. The check is the tracker's, so
/// replay's navigator and the live sensor share it. Cheap: a 64-bit FNV-1a hash of the
/// pixels with the size and type. No pixels are kept: a grabber may reuse its buffer for the
/// next frame, and two different frames share a hash with probability ~5e-20.
#pragma once
#include <opencv2/core.hpp>

#include <cstdint>
#include <optional>

namespace st {

class FrozenFrameCheck {
 public:
  /// The time of the frame `image` repeats, or nothing for a new image (which then becomes
  /// the reference). A run of repeats all repeat the last new image.
  std::optional<double> repeats(const cv::Mat& image, double t_s);
  void reset() { last_t_.reset(); }

 private:
  uint64_t last_hash_ = 0;
  cv::Size last_size_;
  int last_type_ = -1;
  std::optional<double> last_t_;
};

}  // namespace st

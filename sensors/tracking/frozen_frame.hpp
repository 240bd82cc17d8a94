/// @file frozen_frame.hpp
/// A camera that repeats its readout (a frozen image): the same pixels again at a new time
/// would give the old attitude stamped with the new time. Every caller of a StarTracker that
/// receives frames runs this one check before it: replay's navigator, the live sensor and the
/// library's Tracker (frozenFrameResult: one answer for all). Not inside StarTracker::process:
/// hashing a whole frame costs more than tracking it (the tracker reads only its windows),
/// while a caller has just decoded or grabbed the frame anyway. A 64-bit FNV-1a hash of the
/// pixels with the size and type; no pixels are kept (a grabber may reuse its buffer for the
/// next frame), and two different frames share a hash with probability ~5e-20.
#pragma once
#include <opencv2/core.hpp>

#include <cstdint>
#include <optional>

#include "sensors/tracking/frame.hpp"

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

/// The failed frame of a repeat of the frame at `seen_t_s` (FrameFailure::kFrozenImage).
FrameResult frozenFrameResult(double seen_t_s);

class StarTracker;

/// The one edge every frame passes on its way into a tracker (replay's navigator, the live
/// sensor, the library's Tracker): colour (BGR/BGRA) to grey, the frozen-readout check, then
/// StarTracker::process. A repeat gives frozenFrameResult (failure kFrozenImage).
FrameResult processFrame(StarTracker& tracker, FrozenFrameCheck& frozen, const cv::Mat& image,
                         double t_s, const FrameInputs& in);

}  // namespace st

// A camera that repeats its readout (FrameFailure::kFrozenImage): the one check that
// replay's navigator, the live sensor and the library's Tracker run before the tracker
// (tests/navigation/test_navigator_faults.cpp runs it in replay, python/tests through the
// library).
#include <gtest/gtest.h>

#include "sensors/tracking/frozen_frame.hpp"

namespace st {
namespace {

TEST(FrozenFrame, TheSamePixelsInAnotherBufferRepeatAnyChangeDoesNot) {
  FrozenFrameCheck check;
  cv::Mat a(64, 48, CV_16UC1, cv::Scalar(100));
  EXPECT_FALSE(check.repeats(a, 1.0));
  // A grabber may hand the same pixels in a new buffer: still a repeat of t = 1.
  const std::optional<double> seen = check.repeats(a.clone(), 2.0);
  ASSERT_TRUE(seen);
  EXPECT_EQ(*seen, 1.0);
  EXPECT_EQ(*check.repeats(a, 3.0), 1.0);  // a run of repeats: all of the last new image
  cv::Mat b = a.clone();
  b.at<uint16_t>(63, 47) += 1;  // one count in one pixel
  EXPECT_FALSE(check.repeats(b, 4.0));
  // The same bytes in another shape or type are another image.
  EXPECT_FALSE(check.repeats(b.reshape(1, 48), 5.0));
}

TEST(FrozenFrame, TheRefusedFrameNamesTheFrameItRepeats) {
  const FrameResult r = frozenFrameResult(0.9);
  EXPECT_EQ(r.failure, FrameFailure::kFrozenImage);
  EXPECT_FALSE(r.hasAttitude());
  EXPECT_EQ(r.detail, "frozen image: identical to the frame at t = 0.900000 s");
}

}  // namespace
}  // namespace st

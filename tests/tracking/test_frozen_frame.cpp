// A camera that repeats its readout: the star tracker itself refuses the repeat
// (FrameFailure::kFrozenImage), so replay's navigator and the live sensor share the check,
// and the repeat changes nothing of the tracking state.
#include <gtest/gtest.h>

#include "common/conventions.hpp"
#include "sensors/tracking/frozen_frame.hpp"
#include "sensors/tracking/star_tracker.hpp"
#include "tests/tracking/tracker_scoring.hpp"
#include "tests/tracking/tracker_sim.hpp"

namespace st {
namespace {

using test::FrameSimulator;
using namespace test::scoring;

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

TEST(FrozenFrame, TheTrackerRefusesARepeatAndTracksTheNextNewFrame) {
  const SlewMotion motion(startAttitude(), Vec3(deg2rad(0.3), deg2rad(-0.2), deg2rad(0.1)));
  FrameSimulator sim(7);
  StarTracker pipe(test::simDatabase(), test::simCamera(), test::simTrackerOptions());
  FrameInputs in;
  in.rate_body = motion.rateBody(0);
  for (int k = 0; k < 4; ++k) {
    const auto f = sim.frame(motion, 0.1 * k);
    const FrameResult o = pipe.process(f.image, f.t_s, in);
    ASSERT_TRUE(o.hasAttitude()) << "frame " << k << ": " << o.detail;
    // The frame again at the next time: refused, naming the frame it repeats.
    const FrameResult again = pipe.process(f.image, f.t_s + 0.05, in);
    EXPECT_EQ(again.failure, FrameFailure::kFrozenImage) << again.detail;
    EXPECT_FALSE(again.hasAttitude());
    EXPECT_NE(again.detail.find("frozen image: identical to the frame at t = "), std::string::npos)
        << again.detail;
    if (k > 0) {
      EXPECT_EQ(o.mode, StarTrackerMode::kTracking) << "frame " << k << ": " << o.detail;
    }
  }
}

}  // namespace
}  // namespace st

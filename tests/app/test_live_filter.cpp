// LiveFilter (app/live): the real-time filter of `startracker live` re-initialises from the
// next fix after `reinit_after_rejections` gate rejections in a row (through
// AttitudeMekf::resetAttitude, as the navigator does; that it keeps the bias is tested in
// test_mekf.cpp), instead of rejecting every fix after a jump of the sky.
#include <gtest/gtest.h>

#include <chrono>

#include "app/live/live_filter.hpp"
#include "common/attitude.hpp"
#include "common/conventions.hpp"
#include "sensors/mrpt/observation_star_tracker.hpp"
#include "sensors/sim/sim_observations.hpp"

namespace st::app {
namespace {

mrpt::Clock::time_point at(double t) {
  return mrpt::Clock::fromDouble(1.7e9) +
         std::chrono::duration_cast<mrpt::Clock::duration>(std::chrono::duration<double>(t));
}

CObservationStarTracker::Ptr fix(const Quat& q, double sigma, double t) {
  auto o = CObservationStarTracker::Create();
  o->timestamp = at(t);
  o->mode = StarTrackerMode::kTracking;
  o->q_ib = q;
  o->cov_body = Mat3::Identity() * sigma * sigma;
  return o;
}

TEST(LiveFilter, ReinitialisesFromTheNextFixAfterRejectionsInARow) {
  LiveFilterOptions opt;
  opt.latency_s = 0;
  const Quat q0 = attitudeFromRaDecRoll({deg2rad(30.0), deg2rad(10.0), deg2rad(5.0)});
  const Quat q1 = q0 * quatExp(Vec3(0, 0.01, 0));  // the sky jumps by 0.57 deg at t = 5 s
  const double sigma = arcsec2rad(5);
  LiveFilter f(opt);
  for (int k = 0; k <= 1000; ++k) {  // 10 s of a still gyro at 100 Hz, fixes at 5 Hz
    const double t = 0.01 * k;
    f.push(makeGyroObservation(Vec3::Zero(), at(t), "GYRO"));
    if (k % 20 == 0) f.push(fix(t < 5 ? q0 : q1, sigma, t));
  }
  f.flush();
  const LiveFilter::Stats s = f.stats();
  EXPECT_EQ(s.fixes, 51);
  EXPECT_EQ(s.reinits, 1);
  EXPECT_EQ(s.rejected, opt.reinit_after_rejections);  // 5.0, 5.2, 5.4 s; 5.6 s resets
  // 1 initialising fix, 24 before the jump, 3 rejected, 1 resetting, 22 after it.
  EXPECT_EQ(s.accepted, 24 + 22);
  Quat q;
  Mat3 P;
  ASSERT_TRUE(f.current(q, P));
  EXPECT_LT(attitudeError(q, q1).total, 3 * sigma);
  EXPECT_LT(std::sqrt(P.trace()), 2 * sigma);
}

}  // namespace
}  // namespace st::app

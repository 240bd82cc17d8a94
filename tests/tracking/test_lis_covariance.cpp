// KNOWN LIMIT, disabled until fixed (README "Known limits"): the covariance of lost-in-space
// fixes of streaked frames is optimistic by ~1.4x. 40 streaked first frames (3 deg/s, random
// axes in the focal plane, a gyro's rate), each solved lost-in-space: the RMS of the error in
// units of the fix's sigma should be 1 within its sampling error (for 40 N(0, 1), the 99.9 %
// point of sqrt(chi2(40) / 40) is 1.37). Measured: roll 1.48, cross 1.40. Refining the fix in
// pixel space with each streak centroid's full covariance, as tracking does, changed that to
// 1.46 / 1.38 only: the streak centroids' own covariances (detect/streaks) are too small, not
// the solver's weights. On the 4 deg/s slews of scripts/fast_slews.sh this is what puts 4-6 of
// 136 lost-in-space fixes beyond 5 sigma. Run it with --gtest_also_run_disabled_tests.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "common/chi_square.hpp"
#include "common/conventions.hpp"
#include "sensors/tracking/star_tracker.hpp"
#include "tests/tracking/tracker_sim.hpp"

namespace st {
namespace {

TEST(LostInSpaceCovariance, StreakedFixesErrorsMatchTheirSigma) {
  const int kFrames = 40;
  double sum_z2_roll = 0, sum_z2_cross = 0;
  int n = 0;
  for (int k = 0; k < kFrames; ++k) {
    const double az = 2.0 * M_PI * k / kFrames;
    const Vec3 rate = deg2rad(3.0) * Vec3(std::cos(az), std::sin(az), 0.02);
    const SlewMotion motion(attitudeFromRaDecRoll({deg2rad(9.0 * k), deg2rad(-40.0 + 2.0 * k),
                                                   deg2rad(17.0 * k)}),
                            rate);
    test::FrameSimulator sim(4000 + k);
    StarTracker tracker(test::simDatabase(), test::simCamera(), test::simTrackerOptions());
    const auto f = sim.frame(motion, 0.0);
    FrameInputs in;
    in.rate_body = f.rate_body;
    const FrameResult r = tracker.process(f.image, f.t_s, in);
    if (r.mode != StarTrackerMode::kLostInSpace) continue;
    // Body = camera here (body-frame error, roll about z).
    const Vec3 e = quatLog(canonical(f.q_ib.conjugate() * r.q_ib));
    sum_z2_roll += e.z() * e.z() / r.cov_body(2, 2);
    sum_z2_cross += 0.5 * (e.x() * e.x() / r.cov_body(0, 0) + e.y() * e.y() / r.cov_body(1, 1));
    ++n;
  }
  ASSERT_GE(n, 30) << "too few streaked frames solved";
  const double rms_roll = std::sqrt(sum_z2_roll / n), rms_cross = std::sqrt(sum_z2_cross / n);
  const double bound = std::sqrt(chiSquareQuantile(0.999, n) / n);
  std::printf("[ info ] %d streaked lost-in-space fixes: roll error / sigma RMS %.3f, cross %.3f "
              "(bound %.3f)\n", n, rms_roll, rms_cross, bound);
  EXPECT_LT(rms_roll, bound);
  EXPECT_LT(rms_cross, bound);
}

}  // namespace
}  // namespace st

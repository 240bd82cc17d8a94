// Seed 004's Predictive Attitude Determination (eqs. 6.9-6.16) as a Wahba solver: repeated to
// convergence on one frame it is Gauss-Newton on the weighted loss, so it must end at the
// q-method's optimum on noisy problems (the shared suite checks noiseless ones, the NEES and
// the loss). Its start, TRIAD, is not optimal: a PAD that took no step would be TRIAD and
// fail here.
#include <gtest/gtest.h>

#include <cstdio>
#include <random>

#include "common/attitude.hpp"
#include "sensors/attitude/wahba.hpp"
#include "tests/support/wahba_test_utils.hpp"

namespace st {
namespace {

TEST(Pad, EndsAtTheQMethodOptimumOnNoisyProblems) {
  const auto pad = WahbaSolver::create("pad"), qm = WahbaSolver::create("qmethod"),
             triad = WahbaSolver::create("triad");
  ASSERT_TRUE(pad && qm && triad);
  std::mt19937_64 rng(41);
  std::uniform_int_distribution<int> count(2, 20);
  double worst = 0, triad_worst = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    // Every 10th attitude a half turn (w ~ 0), where quaternion solvers need care.
    const Quat q = trial % 10 == 0 ? Quat(0, 0.6, 0, 0.8) : test::wahba_props::randomAttitude(rng);
    auto obs = test::wahba_props::noiseless(q, test::wahba_props::fovDirections(rng, count(rng), deg2rad(10.0)), rng);
    test::wahba_props::addQmmNoise(obs, rng);
    const WahbaSolution p = pad->solve(obs), r = qm->solve(obs), t = triad->solve(obs);
    ASSERT_TRUE(p.ok && r.ok) << p.reason << r.reason;
    worst = std::max(worst, attitudeError(p.q_ib, r.q_ib).total);
    if (t.ok) triad_worst = std::max(triad_worst, attitudeError(t.q_ib, r.q_ib).total);
  }
  std::printf("[ PAD      ] worst distance to the q-method over 3000 problems: %.3g rad (TRIAD, "
              "its start: %.3g rad)\n",
              worst, triad_worst);
  EXPECT_LT(worst, 1e-10);
  EXPECT_GT(triad_worst, 1e-6);  // the start is far enough that the steps are what is tested
}

}  // namespace
}  // namespace st

// The pixel-space refinement (noiseless recovery from a perturbed start, its covariance equal
// to the isotropic Wahba covariance when every centroid is round and alike) and the one
// "solve, drop the worst, re-solve" routine.
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "common/conventions.hpp"
#include "sensors/attitude/drop_worst.hpp"
#include "sensors/attitude/pixel_refinement.hpp"
#include "sensors/attitude/wahba.hpp"
#include "sensors/camera/jacobians.hpp"

namespace st {
namespace {

std::vector<PixelObservation> starsAt(const CameraModel& cam, const Quat& q_ic, double cov_px2) {
  std::vector<PixelObservation> obs;
  const Mat3 R_ic = q_ic.toRotationMatrix();
  for (const Vec2& px : {Vec2(100, 80), Vec2(700, 90), Vec2(400, 300), Vec2(120, 520),
                        Vec2(650, 480), Vec2(300, 150)}) {
    PixelObservation o;
    o.px = px;
    o.cov_px = cov_px2 * Mat2::Identity();
    o.r_i = R_ic * cam.pixelToVector(px);
    obs.push_back(o);
  }
  return obs;
}

TEST(PixelRefinement, RecoversTheAttitudeFromAPerturbedStart) {
  const CameraModel cam = CameraModel::fromFov(800, 600, deg2rad(16.0));
  const Quat q_true = attitudeFromRaDecRoll({deg2rad(84.0), deg2rad(-2.0), deg2rad(25.0)});
  const auto obs = starsAt(cam, q_true, 0.01);
  const Quat start = q_true * quatExp(Vec3(arcsec2rad(30), arcsec2rad(-20), arcsec2rad(60)));
  std::vector<double> e2;
  const PixelRefinement r = refineInPixels(cam, obs, start, 0.001, e2);
  ASSERT_TRUE(r.ok) << r.reason;
  EXPECT_LT(attitudeError(r.q_ic, q_true).total, 1e-10);
  EXPECT_LT(r.chi2, 1e-12);
  ASSERT_EQ(e2.size(), obs.size());

  // Round, equal centroids: the Fisher information is the QMM one, sum (I - b b^T) / sigma^2
  // with sigma the pixel sigma in radians (to first order in the field angle).
  std::vector<VectorObservation> vobs;
  for (const PixelObservation& o : obs) {
    const Vec3 b = q_true.conjugate() * o.r_i;
    vobs.push_back({b, o.r_i, std::sqrt(0.01 + 1e-6) * cam.pixelScale()});
  }
  const WahbaSolution w = WahbaSolver::create("qmethod")->solve(vobs);
  ASSERT_TRUE(w.ok);
  EXPECT_NEAR(r.cov_cam.trace() / w.cov_body.trace(), 1.0, 0.05);
}

TEST(PixelRefinement, AStarBehindTheCameraIsAFailureWithAReason) {
  const CameraModel cam = CameraModel::fromFov(800, 600, deg2rad(16.0));
  const Quat q = Quat::Identity();
  auto obs = starsAt(cam, q, 0.01);
  obs[0].r_i = -obs[0].r_i;
  std::vector<double> e2;
  const PixelRefinement r = refineInPixels(cam, obs, q, 0.001, e2);
  EXPECT_FALSE(r.ok);
  EXPECT_FALSE(r.reason.empty());
}

TEST(DropWorst, DropsTheLargestWhileTheJudgeFailsAndStopsAtTheMinimum) {
  std::vector<double> residual = {1, 9, 2, 7, 3};
  int solves = 0;
  auto judge = [&]() -> DropWorstVerdict {
    const auto it = std::max_element(residual.begin(), residual.end());
    return {*it <= 3.0, std::size_t(it - residual.begin())};
  };
  auto drop = [&](std::size_t worst) {
    residual.erase(residual.begin() + long(worst));
    ++solves;
    return true;
  };
  EXPECT_EQ(dropWorstWhileFailing(residual.size(), 2, judge, drop), DropWorstOutcome::kAccepted);
  EXPECT_EQ(residual, (std::vector<double>{1, 2, 3}));
  EXPECT_EQ(solves, 2);

  residual = {9, 8, 7};
  EXPECT_EQ(dropWorstWhileFailing(residual.size(), 2, judge, drop), DropWorstOutcome::kTooFew);
  EXPECT_EQ(residual.size(), 2u);

  residual = {1, 9};
  auto failing = [&](std::size_t) { return false; };
  EXPECT_EQ(dropWorstWhileFailing(residual.size(), 0, judge, failing),
            DropWorstOutcome::kSolverFailed);
}

}  // namespace
}  // namespace st

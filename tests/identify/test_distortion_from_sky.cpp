// Distortion from the sky (issue: real lenses): lost-in-space with only an approximate field
// of view on frames whose lens moves the corners by up to 4 % of the half-diagonal. The
// identification fits focal length and k1 (k2 where supported) from the stars
// (camera_refine.hpp) and must recover them within their reported uncertainty; without the
// distortion terms the same frames are not solved (teeth).
#include <gtest/gtest.h>

#include "common/conventions.hpp"
#include "sensors/identify/fov_search.hpp"
#include "tests/identify/scene.hpp"

namespace st {
namespace {

CameraModel lens(double k1) {
  const CameraModel pin = CameraModel::fromFov(1280, 800, deg2rad(16.0));
  return CameraModel(1280, 800, pin.fx(), pin.fy(), pin.cx(), pin.cy(), Distortion{k1, 0, 0, 0, 0});
}

/// The corner's displacement by the lens as a fraction of the half-diagonal.
double cornerShift(const CameraModel& cam) {
  const CameraModel pin(cam.width(), cam.height(), cam.fx(), cam.fy(), cam.cx(), cam.cy());
  const Vec3 corner = pin.pixelToVector({-0.5, -0.5});
  const Vec2 centre(cam.cx(), cam.cy());
  return (*cam.vectorToPixel(corner) - Vec2(-0.5, -0.5)).norm() / (Vec2(-0.5, -0.5) - centre).norm();
}

struct Outcome {
  int solved = 0, wrong = 0, k1_outside_4sigma = 0, matches = 0;
  double worst_k1_z = 0;
};

Outcome solveScenes(double k1, const CameraFitPolicy& policy, int scenes) {
  const CameraModel truth = lens(k1);
  // The user's guess: the pinhole field of view, 1 % off.
  const CameraModel guess = CameraModel::fromFov(1280, 800, deg2rad(16.0 * 1.01));
  auto id = StarIdentifier::create("pyramid");
  std::mt19937_64 rng(4242);
  Outcome out;
  test::SceneParams sp;
  sp.noise_px = 0.1;
  sp.false_max = 2;
  for (int s = 0; s < scenes; ++s) {
    const test::Scene sc = test::makeScene(rng, test::testDatabase(), truth, sp, test::randomAttitude(rng));
    if (sc.centroids.size() < 8) continue;
    const FovSearchResult r =
        identifyAndFit(sc.centroids, guess, test::testDatabase(), *id, policy, 0.1);
    if (!r.result.solved()) continue;
    ++out.solved;
    // Wrong = outside its own covariance (chi-square 3 dof, 1e-4 tail).
    if (attitudeNees(r.result.q_ic, r.result.cov_cam, sc.q_ib) > 21.1) ++out.wrong;
    out.matches += static_cast<int>(r.result.matches.size());
    if (!r.camera_fit) continue;
    const double z = (r.camera_fit->theta[kK1] - k1) / r.camera_fit->sigma(kK1);
    out.worst_k1_z = std::max(out.worst_k1_z, std::abs(z));
    if (std::abs(z) > 4) ++out.k1_outside_4sigma;
  }
  return out;
}

TEST(DistortionFromSky, TheLensesUnderTestMoveTheCornerByPercents) {
  EXPECT_NEAR(cornerShift(lens(-1.5)), 0.04, 0.005);
  EXPECT_NEAR(cornerShift(lens(0.8)), 0.022, 0.004);
}

TEST(DistortionFromSky, BarrelAndPincushionLensesSolveAndTheirK1IsRecovered) {
  for (double k1 : {-1.5, -0.5, 0.8}) {
    SCOPED_TRACE("k1 = " + std::to_string(k1));
    const Outcome o = solveScenes(k1, CameraFitPolicy::approximateFov(0.01), 12);
    EXPECT_GE(o.solved, 11);
    EXPECT_EQ(o.wrong, 0);
    EXPECT_EQ(o.k1_outside_4sigma, 0) << "worst |z| " << o.worst_k1_z;
  }
}

TEST(DistortionFromSky, WithoutDistortionTermsTheStrongLensFailsTheSameCriterion) {
  // Teeth: the focal length alone leaves the corners pixels off; the model-error term (capped
  // at 1 px) cannot describe a systematic field, so some frames are lost or reported outside
  // their covariance.
  CameraFitPolicy focal_only = CameraFitPolicy::approximateFov(0.01);
  focal_only.radial_terms = 0;
  const Outcome o = solveScenes(-1.5, focal_only, 12);
  EXPECT_FALSE(o.solved >= 11 && o.wrong == 0) << o.solved << " solved, " << o.wrong << " wrong";
}

}  // namespace
}  // namespace st

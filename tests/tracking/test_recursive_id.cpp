// RecursiveIdentifier (sensors/identify/recursive_id.hpp, seed 002): with a prediction, the
// windows around predicted catalog stars name the stars, and the Mahalanobis gate (3 sqrt(2)
// sigma for round covariances, seed 002 step 5) is what refuses a centroid that is not where
// its star should be.
#include <gtest/gtest.h>

#include <algorithm>

#include "common/conventions.hpp"
#include "sensors/identify/recursive_id.hpp"
#include "sensors/sim/motion.hpp"
#include "tests/tracking/recursive_id_scene.hpp"
#include "tests/tracking/tracker_sim.hpp"

namespace st {
namespace {

using namespace test::recursive_id;

CameraPrediction predictionAt(const Quat& q_ic, double sigma_rad) {
  CameraPrediction p;
  p.q_ic = q_ic;
  p.cov_cam = Mat3::Identity() * sigma_rad * sigma_rad;
  return p;
}


TEST(RecursiveId, ATruePredictionNamesEveryGatedStarRight) {
  const Scene s = scene();
  RecursiveIdentifier rid(test::simDatabase(), test::simCamera(), options());
  RecursiveIdResult r;
  rid.identify(s.frame.image, predictionAt(s.q_ic, arcsec2rad(5.0)), r);
  ASSERT_EQ(r.status, RecursiveIdResult::Status::kOk);
  EXPECT_GE(static_cast<int>(r.stars.size()), 10);
  for (std::size_t k = 0; k < r.stars.size(); ++k) {
    const uint32_t id = test::simDatabase().stars()[r.star_index[k]].id;
    const auto it = std::find_if(s.frame.stars.begin(), s.frame.stars.end(),
                                 [&](const TrueStar& t) { return t.id == id; });
    ASSERT_NE(it, s.frame.stars.end()) << "HIP " << id << " is not in the frame";
    EXPECT_LT((it->px - r.stars[k].px).norm(), 0.5) << "HIP " << id;
  }
}

TEST(RecursiveId, TheGateRefusesCentroidsAwayFromTheirPredictedStars) {
  const Scene s = scene();
  // 2 px (144 arcsec) across the boresight: inside each window (half-size ~4 px), outside the
  // gate of a 5 arcsec prediction (3 sqrt(2) x ~0.1 px).
  const Quat off = s.q_ic * quatExp(Vec3(arcsec2rad(144.0), 0, 0));
  RecursiveIdResult r;
  RecursiveIdentifier rid(test::simDatabase(), test::simCamera(), options());
  rid.identify(s.frame.image, predictionAt(off, arcsec2rad(5.0)), r);
  EXPECT_GT(r.with_centroid, 5) << "the stars must be inside their windows";
  EXPECT_EQ(r.stars.size(), 0u);
  EXPECT_EQ(r.status, RecursiveIdResult::Status::kTooFewInGate);
  // Teeth: without the gate (50 sigma), the same centroids are taken.
  RecursiveIdOptions wide = options();
  wide.gate_sigma = 50.0;
  RecursiveIdentifier loose(test::simDatabase(), test::simCamera(), wide);
  loose.identify(s.frame.image, predictionAt(off, arcsec2rad(5.0)), r);
  EXPECT_GT(r.stars.size(), 5u);
}

}  // namespace
}  // namespace st

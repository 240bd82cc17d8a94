// Teeth for TRIAD's pair choice (seed 001 eq. 32-38; issue 38, item 7). TRIAD keeps its first
// vector ("anchor") exactly and uses only the direction of the second about it, so the anchor
// must be the most precise observation and the second the one that best fixes the rotation
// about it. A list whose best vectors come last tells a solver that follows the rule from one
// that takes the first two.
#include <gtest/gtest.h>

#include <cmath>

#include "common/attitude.hpp"
#include "common/conventions.hpp"
#include "sensors/attitude/wahba.hpp"

namespace st {
namespace {

Vec3 unit(double x, double y, double z) { return Vec3(x, y, z).normalized(); }

/// Three observations of one attitude: a coarse one first (1 deg off), then a nearly
/// parallel precise one, and last the most precise, well separated (both exact).
std::vector<VectorObservation> scene(const Quat& q_ib) {
  const Mat3 R = q_ib.toRotationMatrix();
  const Vec3 r0 = unit(1, 0, 0), r1 = unit(0.05, 1, 0), r2 = unit(0, 0.2, 1);
  // b = R^T r, the coarse one rotated by 1 deg about z.
  const Vec3 b0 = Eigen::AngleAxisd(deg2rad(1.0), Vec3::UnitZ()) * (R.transpose() * r0);
  return {{b0, r0, deg2rad(1.0)},
          {R.transpose() * r1, r1, arcsec2rad(5.0)},
          {R.transpose() * r2, r2, arcsec2rad(1.0)}};
}

TEST(TriadRules, AnchorIsTheMostPreciseVectorAndTheSecondTheMostInformative) {
  const Quat q_ib = quatExp(Vec3(0.3, -0.2, 0.5));
  const auto solver = WahbaSolver::create("triad");
  ASSERT_TRUE(solver);
  const WahbaSolution s = solver->solve(scene(q_ib));
  ASSERT_TRUE(s.ok) << s.reason;
  // Built from the two exact vectors: the attitude itself. Anchoring on the first (coarse)
  // vector, or pairing the anchor with it (its 1 deg error is about the anchor's axis), would
  // carry its 1 deg error.
  const double err = rad2arcsec(attitudeError(s.q_ib, q_ib).total);
  EXPECT_LT(err, 1e-6) << err << " arcsec";
}

}  // namespace
}  // namespace st

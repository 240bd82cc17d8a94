// The least-squares DCM of seed 001 eq. 25-31 (solver "lsq"): exact on noise-free vectors
// that span 3-D, refuses two or coplanar vectors, its 9-unknown fit is not orthogonal under
// noise, and it is measurably worse than the optimal solvers in a camera-sized field.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "common/conventions.hpp"
#include "sensors/attitude/wahba.hpp"
#include "tests/support/wahba_test_utils.hpp"

namespace st {
namespace {

using namespace test::wahba_props;

TEST(LsqDcm, ExactOnThreeIndependentNoiseFreeVectors) {
  const auto lsq = WahbaSolver::create("lsq");
  std::mt19937_64 rng(3);
  for (int t = 0; t < 50; ++t) {
    const Quat q = randomAttitude(rng);
    const Obs obs = noiseless(q, {randomUnit(rng), randomUnit(rng), randomUnit(rng)}, rng);
    const WahbaSolution sol = lsq->solve(obs);
    ASSERT_TRUE(sol.ok) << sol.reason;
    // rounding: eps times the condition of G (up to ~1e4 for three random directions)
    EXPECT_LE(attitudeError(sol.q_ib, q).total, 1e-10);
    EXPECT_LE(lsqDcmOrthogonalityDefect(obs), 1e-10);  // noise-free: M is the rotation
  }
}

TEST(LsqDcm, RefusesTwoOrCoplanarVectors) {
  const auto lsq = WahbaSolver::create("lsq");
  std::mt19937_64 rng(4);
  const Quat q = randomAttitude(rng);
  const WahbaSolution two = lsq->solve(noiseless(q, {Vec3::UnitX(), Vec3::UnitY()}, rng));
  EXPECT_FALSE(two.ok);
  EXPECT_NE(two.reason.find("needs at least 3"), std::string::npos) << two.reason;
  const Vec3 c = Vec3(1, 1, 0).normalized();  // three vectors in the plane z = 0
  const WahbaSolution flat = lsq->solve(noiseless(q, {Vec3::UnitX(), Vec3::UnitY(), c}, rng));
  EXPECT_FALSE(flat.ok);
  EXPECT_NE(flat.reason.find("coplanar"), std::string::npos) << flat.reason;
}

// Noise: the fitted M is not a rotation (the seed's eq. 31 output), and the nearest rotation
// to it is worse than the optimal q-method (measured: 26 % larger RMS error in a 15 deg
// field, 14 % over the whole sky, 8 vectors); its own covariance (NEES in the shared suite)
// predicts that. 400 trials: the RMS ratio is known to ~3 %.
TEST(LsqDcm, NotOrthogonalAndSubOptimal) {
  const auto lsq = WahbaSolver::create("lsq"), opt = WahbaSolver::create("qmethod");
  for (const bool narrow : {true, false}) {
    std::mt19937_64 rng(narrow ? 5 : 6);
    double e_lsq = 0, e_opt = 0, defect = 0;
    constexpr int kN = 400;
    for (int t = 0; t < kN; ++t) {
      const Quat q = randomAttitude(rng);
      std::vector<Vec3> b;
      if (narrow) {
        b = fovDirections(rng, 8, deg2rad(7.5));
      } else {
        for (int k = 0; k < 8; ++k) b.push_back(randomUnit(rng));
      }
      Obs obs = noiseless(q, b, rng);
      addQmmNoise(obs, rng);
      const WahbaSolution a = lsq->solve(obs), o = opt->solve(obs);
      ASSERT_TRUE(a.ok && o.ok) << a.reason << o.reason;
      e_lsq += std::pow(attitudeError(a.q_ib, q).total, 2) / kN;
      e_opt += std::pow(attitudeError(o.q_ib, q).total, 2) / kN;
      defect += lsqDcmOrthogonalityDefect(obs) / kN;
    }
    const double ratio = std::sqrt(e_lsq / e_opt);
    std::cout << "[ LSQ DCM  ] " << (narrow ? "15 deg field" : "whole sky") << ": rms error lsq / "
              << "q-method " << ratio << ", mean |M^T M - I| " << defect << "\n";
    EXPECT_GT(defect, 1e-5);  // sigma ~1e-4: M is visibly not orthogonal
    EXPECT_GT(ratio, 1.08);  // an optimal solver in its place gives 1 and fails this
    EXPECT_LT(ratio, 1.5);
  }
}

}  // namespace
}  // namespace st

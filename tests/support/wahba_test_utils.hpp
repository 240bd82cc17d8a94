/// @file wahba_test_utils.hpp
/// The properties every Wahba solver must have, as calls a solver author runs on a solver
/// (as Ceres ships manifold_test_utils.h). One call runs them all:
///
///   TEST(MySolver, Properties) { st::test::expectWahbaSolverProperties(*makeMySolver()); }
///
/// Every solver in the registry gets them through tests/attitude/test_wahba_solvers.cpp
/// without being named there. The properties:
///  - noiseless recovery to 5e-11 rad (so any two solvers agree to 1e-10), including the
///    180 deg attitudes, two-vector and orthogonal sets, tiny rotations, 200 vectors;
///  - nearly collinear vectors: solved accurately or refused with a reason;
///  - the NEES of the reported covariance inside the chi-square 99 % band, with teeth (a 4x
///    covariance falls out of it);
///  - the reported loss is the Wahba loss at the returned attitude (and chi-square for the
///    solvers that minimise it);
///  - degenerate input answered with ok = false and a reason, never a crash.
#pragma once
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <iostream>
#include <limits>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "common/conventions.hpp"
#include "sensors/attitude/wahba.hpp"

namespace st::test {
namespace wahba_props {

using Obs = std::vector<VectorObservation>;

inline Vec3 randomUnit(std::mt19937_64& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  return Vec3(n(rng), n(rng), n(rng)).normalized();
}

inline Quat randomAttitude(std::mt19937_64& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  return canonical(Quat(n(rng), n(rng), n(rng), n(rng)));
}

/// `n` body directions uniformly inside a cone of half-angle `half_angle` about +z (a camera
/// field of view).
inline std::vector<Vec3> fovDirections(std::mt19937_64& rng, int n, double half_angle) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Vec3> out;
  const double cmin = std::cos(half_angle);
  for (int k = 0; k < n; ++k) {
    const double c = 1.0 - u(rng) * (1.0 - cmin);
    const double s = std::sqrt(1.0 - c * c);
    const double phi = kTwoPi * u(rng);
    out.emplace_back(s * std::cos(phi), s * std::sin(phi), c);
  }
  return out;
}

/// Noiseless pairs: r = R(q_ib) b exactly, sigmas varied so the weighting matters.
inline Obs noiseless(const Quat& q_ib, const std::vector<Vec3>& b, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(5e-5, 2e-4);
  Obs obs;
  for (const Vec3& bk : b) obs.push_back({bk, (q_ib * bk).normalized(), u(rng)});
  return obs;
}

/// Adds the QMM error: isotropic Gaussian with sigma per axis projected onto the plane
/// perpendicular to b (sigma per transverse axis), then renormalised.
inline void addQmmNoise(Obs& obs, std::mt19937_64& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  for (VectorObservation& o : obs) {
    Vec3 e(n(rng), n(rng), n(rng));
    e -= e.dot(o.b) * o.b;
    o.b = (o.b + o.sigma * e).normalized();
  }
}

struct Scenario {
  std::string name;
  Quat q_true;
  Obs obs;
};

/// The nasty cases (Sophus feeds rotations by pi and 1e-5 rad the same way).
inline std::vector<Scenario> noiselessScenarios() {
  std::mt19937_64 rng(20261122);
  const double fov_half = deg2rad(7.5);  // 15 deg FOV
  std::vector<Scenario> s;
  auto add = [&](const std::string& name, const Quat& q, const std::vector<Vec3>& b) {
    s.push_back({name, canonical(q), noiseless(q, b, rng)});
  };
  for (int i = 0; i < 3; ++i)
    add("random_10_" + std::to_string(i), randomAttitude(rng), fovDirections(rng, 10, fov_half));
  add("pi_about_x", quatExp(kPi * Vec3::UnitX()), fovDirections(rng, 10, fov_half));
  add("pi_about_y", quatExp(kPi * Vec3::UnitY()), fovDirections(rng, 10, fov_half));
  add("pi_about_z", quatExp(kPi * Vec3::UnitZ()), fovDirections(rng, 10, fov_half));
  for (int i = 0; i < 4; ++i)
    add("pi_random_axis_" + std::to_string(i), quatExp(kPi * randomUnit(rng)),
        fovDirections(rng, 8, fov_half));
  add("pi_minus_1e-9", quatExp((kPi - 1e-9) * randomUnit(rng)), fovDirections(rng, 8, fov_half));
  add("pi_about_x_two_vectors", quatExp(kPi * Vec3::UnitX()), fovDirections(rng, 2, fov_half));
  add("identity", Quat::Identity(), fovDirections(rng, 10, fov_half));
  add("tiny_1e-12", quatExp(1e-12 * randomUnit(rng)), fovDirections(rng, 10, fov_half));
  add("tiny_1e-6", quatExp(1e-6 * randomUnit(rng)), fovDirections(rng, 10, fov_half));
  add("two_vectors", randomAttitude(rng), fovDirections(rng, 2, fov_half));
  add("three_orthogonal", randomAttitude(rng), {Vec3::UnitX(), Vec3::UnitY(), Vec3::UnitZ()});
  std::vector<Vec3> sky;
  for (int k = 0; k < 200; ++k) sky.push_back(randomUnit(rng));
  add("many_200_all_sky", randomAttitude(rng), sky);
  add("many_60_in_fov", randomAttitude(rng), fovDirections(rng, 60, fov_half));
  return s;
}

/// The loss is W (1 - lambda) with W = sum 1/sigma^2 and lambda ~ 1 known to about 1e3 ulp
/// (a root of a quartic with O(1) terms whose slope is >= 1e-2 for a camera-sized field), so
/// its absolute rounding is about 1e3 eps W.
inline double lossRounding(const Obs& obs) {
  double w = 0;
  for (const VectorObservation& o : obs) w += 1.0 / (o.sigma * o.sigma);
  return 1e3 * std::numeric_limits<double>::epsilon() * w;
}

/// Two-sided 99% band of the mean of N chi-square(3) variables: chi2_{3N}(0.005, 0.995) / N,
/// Wilson-Hilferty (relative error ~1e-4 at 3000 dof).
inline std::pair<double, double> neesMeanBand(int n_trials) {
  const double k = 3.0 * n_trials;
  const double z = 2.5758293035489;  // standard normal 0.995 quantile
  const double h = 2.0 / (9.0 * k);
  const auto q = [&](double zz) { return k * std::pow(1.0 - h + zz * std::sqrt(h), 3) / n_trials; };
  return {q(-z), q(z)};
}

}  // namespace wahba_props

/// Every solver recovers the truth to 5e-11 rad, so any two agree to 1e-10 rad (triangle
/// inequality); the agreement with the q-method reference is also checked directly.
inline void expectNoiselessRecovery(const WahbaSolver& solver) {
  using namespace wahba_props;
  const auto reference = WahbaSolver::create("qmethod");
  ASSERT_NE(reference, nullptr);
  for (const Scenario& sc : noiselessScenarios()) {
    SCOPED_TRACE(solver.name() + " " + sc.name);
    const WahbaSolution sol = solver.solve(sc.obs);
    if (static_cast<int>(sc.obs.size()) < solver.minVectors()) {  // refused, with a reason
      EXPECT_FALSE(sol.ok);
      EXPECT_NE(sol.reason.find("needs at least"), std::string::npos) << sol.reason;
      continue;
    }
    ASSERT_TRUE(sol.ok) << sol.reason;
    EXPECT_GE(sol.q_ib.w(), 0.0);
    EXPECT_NEAR(sol.q_ib.norm(), 1.0, 1e-15);
    EXPECT_LE(attitudeError(sol.q_ib, sc.q_true).total, 5e-11);
    const WahbaSolution ref = reference->solve(sc.obs);
    ASSERT_TRUE(ref.ok) << ref.reason;
    EXPECT_LE(attitudeError(sol.q_ib, ref.q_ib).total, 1e-10);
    EXPECT_LE(sol.loss, lossRounding(sc.obs));  // noiseless: zero up to the rounding
  }
}

/// Nearly collinear vectors (still above kWahbaMinGeometry). Graceful means: solved with a
/// numerical error below 1e-3 of the smallest reported 1-sigma, or refused with a reason
/// (QUEST and ESOQ-2 refuse when their characteristic-equation root cannot separate the two
/// nearly equal eigenvalues of K). At 1e-2 rad (the closest real star pairs) every solver must
/// solve; below the geometry threshold every solver must refuse.
inline void expectNearCollinearGraceful(const WahbaSolver& solver) {
  using namespace wahba_props;
  std::mt19937_64 rng(7);
  for (double spread : {1e-2, 1e-3, 1e-4}) {
    SCOPED_TRACE(solver.name() + " spread " + std::to_string(spread));
    const Quat q_true = randomAttitude(rng);
    const Vec3 b1 = Vec3::UnitZ();
    const Vec3 b2 = quatExp(spread * Vec3::UnitX()) * b1;
    const Vec3 b3 = quatExp(0.5 * spread * Vec3::UnitY()) * b1;
    const WahbaSolution sol = solver.solve(noiseless(q_true, {b1, b2, b3}, rng));
    if (spread >= 1e-2) {
      ASSERT_TRUE(sol.ok) << sol.reason;
    }
    std::cout << "[ COLLINEAR] " << solver.name() << " spread " << spread << ": "
              << (sol.ok ? "solved" : "refused: " + sol.reason) << "\n";
    if (!sol.ok) {
      EXPECT_NE(sol.reason.find("collinear"), std::string::npos) << sol.reason;
      continue;
    }
    const double err = attitudeError(sol.q_ib, q_true).total;
    const Vec3 var = sol.cov_body.eigenvalues().real();
    const double sigma_min = std::sqrt(var.minCoeff()), sigma_max = std::sqrt(var.maxCoeff());
    EXPECT_LE(err, 1e-3 * sigma_min) << "err " << err << " sigma_min " << sigma_min;
    EXPECT_GT(sigma_max, 0.1 * 2e-4 / spread);  // roll sigma ~ sigma / spread
  }
  const Quat q_true = randomAttitude(rng);
  const WahbaSolution sol = solver.solve(
      noiseless(q_true, {Vec3::UnitZ(), quatExp(1e-7 * Vec3::UnitX()) * Vec3::UnitZ()}, rng));
  EXPECT_FALSE(sol.ok);
  EXPECT_NE(sol.reason.find("parallel"), std::string::npos) << sol.reason;
}

/// Mean NEES of the reported covariance over `trials` noisy random problems inside the
/// two-sided 99 % chi-square band; teeth: the same errors judged with 4P fall out of it.
inline void expectNeesInChiSquareBand(const WahbaSolver& solver, int trials = 1000) {
  using namespace wahba_props;
  std::mt19937_64 rng(12345);
  std::uniform_int_distribution<int> n_stars(4, 12);
  double nees_sum = 0, nees_sum_scaled = 0;
  for (int t = 0; t < trials; ++t) {
    const Quat q_true = randomAttitude(rng);
    Obs obs = noiseless(q_true, fovDirections(rng, n_stars(rng), deg2rad(7.5)), rng);
    addQmmNoise(obs, rng);
    const WahbaSolution sol = solver.solve(obs);
    ASSERT_TRUE(sol.ok) << solver.name() << ": " << sol.reason;
    nees_sum += attitudeNees(sol.q_ib, sol.cov_body, q_true);
    nees_sum_scaled += attitudeNees(sol.q_ib, 4.0 * sol.cov_body, q_true);
  }
  const auto [lo, hi] = neesMeanBand(trials);
  const double mean = nees_sum / trials, mean_scaled = nees_sum_scaled / trials;
  EXPECT_GT(mean, lo) << solver.name();
  EXPECT_LT(mean, hi) << solver.name();
  EXPECT_FALSE(mean_scaled > lo && mean_scaled < hi) << "scaled mean " << mean_scaled;
  std::cout << "[ NEES     ] " << solver.name() << ": mean " << mean << " band [" << lo << ", "
            << hi << "], 4P mean " << mean_scaled << "\n";
}

/// The reported loss is the Wahba loss at the returned attitude (to 1e-6 relative plus the
/// rounding of W (1 - lambda)); a 1-sigma change of attitude changes it by O(1), so this has
/// teeth. For a solver that minimises the loss, 2 * loss is chi-square(2n - 3): the mean
/// checks the a_k = 1/sigma^2 normalisation.
inline void expectLossIsWahbaLoss(const WahbaSolver& solver) {
  using namespace wahba_props;
  constexpr int kTrials = 300;
  std::mt19937_64 rng(999);
  double chi2_sum = 0, dof_sum = 0;
  for (int t = 0; t < kTrials; ++t) {
    const Quat q_true = randomAttitude(rng);
    const int n = 3 + t % 10;
    Obs obs = noiseless(q_true, fovDirections(rng, n, deg2rad(7.5)), rng);
    addQmmNoise(obs, rng);
    const WahbaSolution sol = solver.solve(obs);
    ASSERT_TRUE(sol.ok) << sol.reason;
    const double direct = wahbaLoss(obs, sol.q_ib);
    const double tol = 1e-6 * direct + lossRounding(obs);
    ASSERT_NEAR(sol.loss, direct, tol) << solver.name() << " trial " << t;
    Eigen::SelfAdjointEigenSolver<Mat3> eig(sol.cov_body);
    const Vec3 step = std::sqrt(eig.eigenvalues()(2)) * eig.eigenvectors().col(2);
    // Both directions: from a sub-optimal attitude (triad, lsq) one of the two steps may go
    // downhill and cancel the curvature; their sum is the curvature, O(1) for a 1-sigma step.
    EXPECT_GT(std::max(std::abs(wahbaLoss(obs, sol.q_ib * quatExp(step)) - sol.loss),
                       std::abs(wahbaLoss(obs, sol.q_ib * quatExp(-step)) - sol.loss)),
              100 * tol);
    chi2_sum += 2.0 * sol.loss;
    dof_sum += 2.0 * n - 3.0;
  }
  if (solver.minimisesLoss()) {  // a sub-optimal solver's loss is larger than chi-square
    const double ratio = chi2_sum / dof_sum;  // +-3 sigma = 3 sqrt(2 dof) / dof
    EXPECT_NEAR(ratio, 1.0, 3.0 * std::sqrt(2.0 / dof_sum)) << solver.name() << ": 2*loss/dof";
  }
}

/// Degenerate input: ok = false with a reason, never a crash or an attitude.
inline void expectDegenerateInputRefused(const WahbaSolver& solver) {
  using Obs = wahba_props::Obs;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const Vec3 x = Vec3::UnitX(), y = Vec3::UnitY(), z = Vec3::UnitZ();
  const std::vector<std::pair<std::string, Obs>> cases = {
      {"empty", {}},
      {"one_vector", {{x, x, 1e-4}}},
      {"duplicate", {{x, x, 1e-4}, {x, x, 1e-4}}},
      {"antiparallel", {{x, y, 1e-4}, {-x, -y, 1e-4}}},
      {"all_parallel", {{z, x, 1e-4}, {z, x, 2e-4}, {z, x, 3e-4}, {z, x, 1e-4}}},
      {"reference_parallel", {{x, z, 1e-4}, {y, z, 1e-4}}},
      {"non_unit_b", {{2 * x, x, 1e-4}, {y, y, 1e-4}}},
      {"non_unit_r", {{x, x, 1e-4}, {y, 0.5 * y, 1e-4}}},
      {"zero_b", {{Vec3::Zero(), x, 1e-4}, {y, y, 1e-4}}},
      {"nan_b", {{Vec3(nan, 0, 1), x, 1e-4}, {y, y, 1e-4}}},
      {"nan_r", {{x, Vec3(nan, 0, 1), 1e-4}, {y, y, 1e-4}}},
      {"nan_sigma", {{x, x, nan}, {y, y, 1e-4}}},
      {"zero_sigma", {{x, x, 0.0}, {y, y, 1e-4}}},
      {"negative_sigma", {{x, x, -1e-4}, {y, y, 1e-4}}},
      {"infinite_sigma", {{x, x, inf}, {y, y, 1e-4}}},
  };
  for (const auto& [name, obs] : cases) {
    SCOPED_TRACE(solver.name() + " " + name);
    const WahbaSolution sol = solver.solve(obs);
    EXPECT_FALSE(sol.ok);
    EXPECT_FALSE(sol.reason.empty());
  }
}

/// All of the above, for a solver author's one-line test.
inline void expectWahbaSolverProperties(const WahbaSolver& solver) {
  expectNoiselessRecovery(solver);
  expectNearCollinearGraceful(solver);
  expectNeesInChiSquareBand(solver);
  expectLossIsWahbaLoss(solver);
  expectDegenerateInputRefused(solver);
}

}  // namespace st::test

/// @file wahba.hpp
/// Wahba's problem: the attitude q_ib that best maps measured body vectors b_k onto known
/// inertial vectors r_k (r_k ~= R(q_ib) b_k), with its loss and body-frame covariance.
///
/// Measurement model (Shuster's QUEST measurement model, QMM): b_k is the true direction plus
/// an error perpendicular to it with covariance sigma_k^2 (I - b_k b_k^T), i.e. sigma_k [rad]
/// per transverse axis. The weights are therefore a_k = 1 / sigma_k^2, and
///   loss(q) = 1/2 sum_k a_k |b_k - R(q)^T r_k|^2          (seed 004 eq. 6.18, a_k = 1/sigma^2)
/// so that under the QMM 2 * loss at the optimum is chi-square with 2n - 3 degrees of freedom.
/// (Inside, the solvers normalise the weights to sum 1, a_k = sigma_tot^2 / sigma_k^2 with
/// 1/sigma_tot^2 = sum 1/sigma_k^2, seed 004 eq. 6.35/6.36, and scale the loss back.)
///
/// Covariance: every optimal solver (qmethod, quest, esoq2, svd, foam) reports the inverse
/// Fisher information of the QMM, P = (sum_k a_k (I - b_k b_k^T))^-1 in the body frame
/// (Shuster 1989; seed 004 eq. 6.17 and 6.34 x4, since 6.34 is the covariance of the quaternion
/// vector part = dtheta/2), svd and foam through their own closed forms (eq. 6.52, 6.58), which
/// equal it to first order. triad reports Shuster & Oh's (1981) covariance of the TRIAD estimate
/// from its two vectors.
///
/// Family: `solve()` validates the input, times the call and keeps the quaternion canonical;
/// implementers override the private doSolve(), which may assume at least minVectors() (2)
/// finite unit vector pairs with positive finite sigmas and non-parallel geometry. Names and
/// help come from the one table in registry.cpp: a new solver is its own file defining
/// `std::unique_ptr<WahbaSolver> makeXSolver()` plus one line in that table (or, for a solver
/// compiled into an executable, one ST_REGISTER_FAMILY_MEMBER line,
/// common/family_registry.hpp). The shared property suite (tests/support/wahba_test_utils.hpp)
/// runs over every registered name.
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "common/attitude.hpp"

namespace st {

/// One matched vector pair.
struct VectorObservation {
  Vec3 b;        ///< measured unit vector, body/camera frame
  Vec3 r;        ///< reference unit vector, inertial frame
  double sigma;  ///< [rad] 1-sigma error of b per transverse axis (QMM)
  /// [rad^2] the full covariance of b when its errors are anisotropic (a streak, binned
  /// pixels), in the plane across b; zero = sigma^2 (I - b b^T). Only `pad` uses it (seed 004
  /// eq. 6.13's R_i); the other solvers take `sigma`.
  Mat3 cov = Mat3::Zero();
};

struct WahbaSolution {
  bool ok = false;
  std::string reason;            ///< why not ok (empty when ok)
  Quat q_ib = Quat::Identity();  ///< canonical (w >= 0); r ~= R(q_ib) * b
  double loss = 0;               ///< Wahba loss at q_ib with a_k = 1/sigma_k^2 (see file comment)
  Mat3 cov_body = Mat3::Zero();  ///< [rad^2] covariance of dtheta, R_true = R_est Exp(dtheta)
  double solve_time_s = 0;       ///< wall time spent in solve(), validation included [s]
};

class WahbaSolver {  // r ~= R(q_ib) * b
 public:
  /// Validates `obs` (>= 2 pairs, finite unit vectors, sigma > 0, b's and r's not all
  /// parallel); on bad input returns ok = false with the reason, never throws.
  WahbaSolution solve(const std::vector<VectorObservation>& obs) const;  // non-virtual entry
  virtual std::string name() const = 0;
  /// True for the optimal solvers, whose loss is Wahba's minimum (2 * loss ~ chi-square
  /// (2n - 3) under the QMM); a sub-optimal one (TRIAD) overrides it with false.
  virtual bool minimisesLoss() const { return true; }
  /// Fewest vector pairs the method can solve (2; the least-squares DCM needs 3 independent
  /// ones). solve() refuses fewer with a reason.
  virtual int minVectors() const { return 2; }

  using Make = std::unique_ptr<WahbaSolver>();  ///< a member's factory (function type)
  using Factory = Make*;
  /// Runtime hook behind ST_REGISTER_FAMILY_MEMBER (common/family_registry.hpp).
  static void registerMember(const std::string& name, const std::string& help, Factory make);
  /// nullptr and *error = "unknown ... valid: ..." for an unknown name.
  static std::unique_ptr<WahbaSolver> create(const std::string& name, std::string* error = nullptr);
  static std::vector<std::string> names();  // from the one registry table
  static std::string defaultName();         // "quest"
  /// One-line description of a solver (empty for an unknown name).
  static std::string help(const std::string& name);
  virtual ~WahbaSolver() = default;

 private:
  virtual WahbaSolution doSolve(const std::vector<VectorObservation>& obs) const = 0;
};

/// |M^T M - I|_F of the unprojected least-squares DCM M of seed 001 eq. 31 (solver "lsq",
/// which reports M's nearest rotation): how far the 9-unknown fit is from a rotation.
double lsqDcmOrthogonalityDefect(const std::vector<VectorObservation>& obs);

/// Wahba loss 1/2 sum_k |b_k - R(q_ib)^T r_k|^2 / sigma_k^2 of an attitude (no validation).
double wahbaLoss(const std::vector<VectorObservation>& obs, const Quat& q_ib);

/// Observations whose geometry is weaker than this are rejected: the smallest eigenvalue of
/// I - sum_k a_k b_k b_k^T (normalised weights) bounds the information about the rotation
/// about the vectors' common direction; 1e-10 is a spread of about 1e-5 rad (2 arcsec).
constexpr double kWahbaMinGeometry = 1e-10;

}  // namespace st

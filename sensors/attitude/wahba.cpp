#include "sensors/attitude/wahba.hpp"

#include <chrono>
#include <cmath>
#include <sstream>

namespace st {
namespace {

// A vector further than this from unit length is rejected rather than silently normalised:
// it means the caller mixed up frames or forgot to normalise, not measurement noise.
constexpr double kUnitTolerance = 1e-6;

std::string checkVector(const Vec3& v, std::size_t k, const char* which) {
  const bool finite = v.allFinite();
  if (finite && std::abs(v.norm() - 1.0) <= kUnitTolerance)
    return {};  // the common case: no stream
  std::ostringstream os;
  os << "observation " << k << ": " << which;
  if (!finite) {
    os << " is not finite";
  } else {
    os << " is not a unit vector (norm " << v.norm() << ")";
  }
  return os.str();
}

// Smallest eigenvalue-bound of I - sum a_k v_k v_k^T (a_k normalised): det <= lambda_min since
// the eigenvalues sum to 2 and the other two multiply to at most 1.
template <typename Get>
double geometryStrength(const std::vector<VectorObservation>& obs, Get get) {
  double wsum = 0;
  Mat3 M = Mat3::Zero();
  for (const VectorObservation& o : obs) {
    const double a = 1.0 / (o.sigma * o.sigma);
    wsum += a;
    M.noalias() += a * get(o) * get(o).transpose();
  }
  return (Mat3::Identity() - M / wsum).determinant();
}

std::string validate(const std::vector<VectorObservation>& obs) {
  if (obs.size() < 2) {
    return "need at least 2 vector observations, got " + std::to_string(obs.size());
  }
  for (std::size_t k = 0; k < obs.size(); ++k) {
    std::string why = checkVector(obs[k].b, k, "b");
    if (why.empty()) why = checkVector(obs[k].r, k, "r");
    if (!why.empty()) return why;
    if (!std::isfinite(obs[k].sigma) || !(obs[k].sigma > 0)) {
      std::ostringstream os;
      os << "observation " << k << ": sigma must be finite and > 0, got " << obs[k].sigma;
      return os.str();
    }
  }
  if (geometryStrength(obs, [](const VectorObservation& o) { return o.b; }) < kWahbaMinGeometry) {
    return "measured vectors are (nearly) parallel: the rotation about them is unobservable";
  }
  if (geometryStrength(obs, [](const VectorObservation& o) { return o.r; }) < kWahbaMinGeometry) {
    return "reference vectors are (nearly) parallel: the rotation about them is unobservable";
  }
  return {};
}

}  // namespace

WahbaSolution WahbaSolver::solve(const std::vector<VectorObservation>& obs) const {
  const auto t0 = std::chrono::steady_clock::now();
  WahbaSolution sol;
  sol.reason = validate(obs);
  if (sol.reason.empty() && static_cast<int>(obs.size()) < minVectors())
    sol.reason = name() + ": needs at least " + std::to_string(minVectors()) +
                 " vector observations, got " + std::to_string(obs.size());
  if (sol.reason.empty()) {
    sol = doSolve(obs);
    if (sol.ok &&
        (!sol.q_ib.coeffs().allFinite() || !sol.cov_body.allFinite() || !std::isfinite(sol.loss))) {
      sol.ok = false;
      sol.reason = name() + ": non-finite result";
    }
    if (sol.ok) sol.q_ib = canonical(sol.q_ib);
  }
  sol.ok = sol.ok && sol.reason.empty();
  if (!sol.ok && sol.reason.empty()) sol.reason = name() + ": failed";
  sol.solve_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return sol;
}

double wahbaLoss(const std::vector<VectorObservation>& obs, const Quat& q_ib) {
  const Mat3 A = q_ib.normalized().toRotationMatrix().transpose();  // A = R_ib^T: r -> b
  double loss = 0;
  for (const VectorObservation& o : obs) {
    loss += (o.b - A * o.r).squaredNorm() / (o.sigma * o.sigma);  // seed 004 eq. 6.18
  }
  return 0.5 * loss;
}

}  // namespace st

// Predictive Attitude Determination (Crassidis & Markley 1997; seed 004 sec. 6.1.2): the
// attitude is moved by the "model error" d that best explains the residuals b - A r (eq. 6.13,
// its isotropic form 6.16) through the quaternion kinematics (eq. 6.9); repeated on one frame
// from TRIAD's attitude until d vanishes, it is Gauss-Newton on the weighted loss, so it ends
// at Wahba's optimum. Covariance: eq. 6.15 (6.17 as printed lacks the transpose that makes it
// positive).
//
// With A = R_ib^T (b = A r) and a_k = A r_k, eq. 6.13 with R_k^-1 = I / sigma_k^2 reads
//   M = sum w_k [a_k x][a_k x]^T = sum w_k (I - a_k a_k^T),   w_k = 1 / sigma_k^2,
//   delta = d dt = -M^-1 sum w_k a_k x b_k,
// and eq. 6.9 over dt turns A by -delta: A <- Exp(-[delta x]) A.
#include <Eigen/Dense>
#include <cmath>
#include <vector>

#include "sensors/attitude/wahba_math.hpp"

namespace st {

std::unique_ptr<WahbaSolver> makeTriadSolver();

namespace {

/// Pseudo-inverse of a covariance (eigenvalues below 1e-12 of the largest count as zero).
Mat3 pseudoInverse(const Mat3& c) {
  const Eigen::SelfAdjointEigenSolver<Mat3> es(c);
  const Vec3 l = es.eigenvalues();
  Vec3 inv = Vec3::Zero();
  for (int i = 0; i < 3; ++i)
    if (l(i) > 1e-12 * l.maxCoeff()) inv(i) = 1.0 / l(i);
  return es.eigenvectors() * inv.asDiagonal() * es.eigenvectors().transpose();
}

/// The steps after which the correction is below rounding (Gauss-Newton from TRIAD: 2-4).
constexpr int kMaxSteps = 30;

class PadSolver final : public WahbaSolver {
 public:
  std::string name() const override { return "pad"; }

 private:
  WahbaSolution doSolve(const std::vector<VectorObservation>& obs) const override {
    const WahbaSolution start = triad_->solve(obs);
    if (!start.ok) return start;
    Mat3 A = start.q_ib.toRotationMatrix().transpose();
    // R_i^+ of each anisotropic star, once (zero: the isotropic sigma is used).
    std::vector<Mat3> weight(obs.size(), Mat3::Zero());
    for (std::size_t i = 0; i < obs.size(); ++i)
      if (!obs[i].cov.isZero(0)) weight[i] = pseudoInverse(obs[i].cov);
    Mat3 M = Mat3::Zero();
    for (int step = 0; step < kMaxSteps; ++step) {
      M.setZero();
      Vec3 g = Vec3::Zero();
      for (std::size_t i = 0; i < obs.size(); ++i) {
        const VectorObservation& o = obs[i];
        const Vec3 a = A * o.r;
        if (o.cov.isZero(0)) {
          const double w = 1.0 / (o.sigma * o.sigma);
          M += w * (Mat3::Identity() - a * a.transpose());  // eq. 6.13's sum, isotropic (6.16)
          g += w * a.cross(o.b);
        } else {
          // eq. 6.13 with the full R_i (rank 2 across b: its pseudo-inverse; [a x] removes
          // the part along a ~ b anyway).
          const Mat3 S = skew(a);
          M += S * weight[i] * S.transpose();
          g += S * weight[i] * (o.b - a);
        }
      }
      const Vec3 delta = -M.ldlt().solve(g);  // eq. 6.13: d dt
      const double angle = delta.norm();
      if (!std::isfinite(angle)) break;
      if (angle > 0) A = Eigen::AngleAxisd(-angle, delta / angle).toRotationMatrix() * A;  // eq. 6.9
      if (angle < 1e-15) break;
    }
    WahbaSolution sol;
    sol.ok = true;
    sol.q_ib = wahba_detail::quatFromAttitudeMatrix(A);
    double loss = 0;
    for (const VectorObservation& o : obs) loss += (1.0 - o.b.dot(A * o.r)) / (o.sigma * o.sigma);
    sol.loss = std::max(0.0, loss);
    sol.cov_body = M.inverse();  // eq. 6.15 at the solution
    return sol;
  }

  std::unique_ptr<WahbaSolver> triad_ = makeTriadSolver();
};

}  // namespace

std::unique_ptr<WahbaSolver> makePadSolver() { return std::make_unique<PadSolver>(); }

}  // namespace st

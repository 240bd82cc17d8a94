// TRIAD (seed 001 eq. 32-38): exact for two vector pairs, the first ("anchor") kept exactly.
// Pair choice: the anchor is the observation with the largest weight 1/sigma^2; the second is
// the one that best fixes the rotation about the anchor, max |b1 x bk|^2 / sigma_k^2 (for two
// well-separated vectors these are simply the two highest-weight ones).
// Covariance: TRIAD is not the optimal estimator, so it reports its own (Shuster & Oh 1981):
//   P = s1^2 I + [ (s2^2 - s1^2) b1 b1^T + s1^2 (b1.b2)(b1 b2^T + b2 b1^T) ] / |b1 x b2|^2
// (linear propagation of the QMM errors of b1 and b2 through the triads, body frame).
#include <cmath>

#include "sensors/attitude/wahba_math.hpp"

namespace st {
namespace {

Mat3 triad(const Vec3& v1, const Vec3& v2) {
  const Vec3 t2 = v1.cross(v2).normalized();  // seed 001 eq. 33/34
  Mat3 m;
  m.col(0) = v1;
  m.col(1) = t2;
  m.col(2) = v1.cross(t2);
  return m;
}

class TriadSolver final : public WahbaSolver {
 public:
  std::string name() const override { return "triad"; }
  bool minimisesLoss() const override { return false; }  // exact on two vectors only

 private:
  WahbaSolution doSolve(const std::vector<VectorObservation>& obs) const override {
    std::size_t i1 = 0;
    for (std::size_t k = 1; k < obs.size(); ++k)
      if (obs[k].sigma < obs[i1].sigma) i1 = k;
    const Vec3& b1 = obs[i1].b;
    std::size_t i2 = i1;
    double best = 0;
    for (std::size_t k = 0; k < obs.size(); ++k) {
      if (k == i1) continue;
      const double info = b1.cross(obs[k].b).squaredNorm() / (obs[k].sigma * obs[k].sigma);
      if (info > best) {
        best = info;
        i2 = k;
      }
    }
    WahbaSolution sol;
    const Vec3& b2 = obs[i2].b;
    const double sin2_b = b1.cross(b2).squaredNorm();
    const double sin2_r = obs[i1].r.cross(obs[i2].r).squaredNorm();
    if (i2 == i1 || sin2_b < kWahbaMinGeometry || sin2_r < kWahbaMinGeometry) {
      sol.reason = "triad: no second vector separated from the anchor";
      return sol;
    }
    // R_ib maps the body triad onto the reference triad: R_ib = M_ref M_obs^T (seed 001 eq. 38
    // transposed, since the seed's A = R_ib^T).
    const Mat3 R_ib = triad(obs[i1].r, obs[i2].r) * triad(b1, b2).transpose();
    const double s1 = obs[i1].sigma * obs[i1].sigma;
    const double s2 = obs[i2].sigma * obs[i2].sigma;
    const double c = b1.dot(b2);
    sol.ok = true;
    sol.q_ib = canonical(Quat(R_ib));
    sol.loss = wahbaLoss(obs, sol.q_ib);  // TRIAD has no loss of its own: evaluate it
    sol.cov_body = s1 * Mat3::Identity() + ((s2 - s1) * b1 * b1.transpose() +
                                            s1 * c * (b1 * b2.transpose() + b2 * b1.transpose())) /
                                               sin2_b;
    return sol;
  }
};

}  // namespace

std::unique_ptr<WahbaSolver> makeTriadSolver() { return std::make_unique<TriadSolver>(); }

}  // namespace st

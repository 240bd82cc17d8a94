#include "sensors/attitude/joint_fix.hpp"

#include <Eigen/Cholesky>

namespace st {

JointFix jointFix(const std::vector<HeadFix>& heads) {
  JointFix out;
  if (heads.empty()) {
    out.reason = "no head fix";
    return out;
  }
  std::vector<Mat3> W(heads.size());
  Mat3 N = Mat3::Zero();
  for (std::size_t h = 0; h < heads.size(); ++h) {
    const Eigen::LLT<Mat3> llt(heads[h].cov_body);
    if (llt.info() != Eigen::Success || !heads[h].cov_body.allFinite()) {
      out.reason = "head " + std::to_string(h) + ": covariance not positive definite";
      return out;
    }
    W[h] = llt.solve(Mat3::Identity());
    N += W[h];
  }
  const Eigen::LLT<Mat3> info(N);
  out.q_ib = canonical(heads.front().q_ib);
  out.dof = 3 * (static_cast<int>(heads.size()) - 1);
  // Gauss-Newton: the heads agree to arcseconds, where Log's Jacobian is the identity to
  // ~1e-5, so each step is the information-weighted mean of the residuals; three converge.
  constexpr int kSteps = 3;
  for (int it = 0; it <= kSteps; ++it) {
    Vec3 g = Vec3::Zero();
    out.chi2 = 0;
    for (std::size_t h = 0; h < heads.size(); ++h) {
      const Vec3 e = quatLog(canonical(heads[h].q_ib.conjugate() * out.q_ib));
      g += W[h] * e;
      out.chi2 += e.dot(W[h] * e);
    }
    if (it == kSteps) break;
    out.q_ib = canonical(out.q_ib * quatExp(-info.solve(g)));
  }
  out.cov_body = info.solve(Mat3::Identity());
  out.cov_body = 0.5 * (out.cov_body + out.cov_body.transpose());
  out.ok = true;
  return out;
}

}  // namespace st

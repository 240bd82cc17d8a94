// Markley's SVD method: B = U S V^T, A_opt = U diag(1, 1, d) V^T with d = det U det V
// (seed 004 eq. 6.38-6.50); covariance from the same decomposition (eq. 6.51/6.52).
#include <Eigen/SVD>
#include <algorithm>

#include "sensors/attitude/wahba_math.hpp"

namespace st {
namespace {

class SvdSolver final : public WahbaSolver {
 public:
  std::string name() const override { return "svd"; }

 private:
  WahbaSolution doSolve(const std::vector<VectorObservation>& obs) const override {
    using namespace wahba_detail;
    const Problem p = buildProblem(obs);
    const Eigen::JacobiSVD<Mat3> svd(p.B, Eigen::ComputeFullU | Eigen::ComputeFullV);
    const Mat3& U = svd.matrixU();
    const Mat3& V = svd.matrixV();
    const Vec3 s = svd.singularValues();                 // s1 >= s2 >= s3 >= 0 (eq. 6.41)
    const double d = U.determinant() * V.determinant();  // eq. 6.46
    const Vec3 s_prime(s(0), s(1), d * s(2));            // eq. 6.45
    const Mat3 A = U * Vec3(1.0, 1.0, d).asDiagonal() * V.transpose();  // eq. 6.50
    const double loss_n = 1.0 - s_prime.sum();                          // eq. 6.49
    const Vec3 D(s_prime(1) + s_prime(2), s_prime(2) + s_prime(0),
                 s_prime(0) + s_prime(1));  // 6.51
    // eq. 6.52 in the principal frame: U (the body side of B) rotates it into the body frame;
    // diag(1,1,det U) only flips a column of U, which cancels in U X U^T.
    const Vec3 diagP = (Vec3::Ones() - s_prime).cwiseQuotient(D.cwiseProduct(D));

    WahbaSolution sol;
    sol.ok = true;
    sol.q_ib = quatFromAttitudeMatrix(A);
    sol.loss = p.weight_sum * std::max(0.0, loss_n);
    sol.cov_body = p.sigma_tot2 * U * diagP.asDiagonal() * U.transpose();
    return sol;
  }
};

}  // namespace

std::unique_ptr<WahbaSolver> makeSvdSolver() { return std::make_unique<SvdSolver>(); }

}  // namespace st

// Davenport's q-method: the optimal quaternion is the eigenvector of K with the largest
// eigenvalue (seed 004 eq. 6.21-6.29, seed 001 eq. 42-51). The reference the others are
// checked against: a full symmetric eigen-decomposition, no iteration of our own.
#include <Eigen/Eigenvalues>
#include <algorithm>

#include "sensors/attitude/wahba_math.hpp"

namespace st {
namespace {

class QMethodSolver final : public WahbaSolver {
 public:
  std::string name() const override { return "qmethod"; }

 private:
  WahbaSolution doSolve(const std::vector<VectorObservation>& obs) const override {
    using namespace wahba_detail;
    const Problem p = buildProblem(obs);
    const KTerms k = kTerms(p.B);
    Eigen::Matrix4d K;  // seed 004 eq. 6.21
    K.topLeftCorner<3, 3>() = k.S - k.sigma * Mat3::Identity();
    K.topRightCorner<3, 1>() = k.z;
    K.bottomLeftCorner<1, 3>() = k.z.transpose();
    K(3, 3) = k.sigma;
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d> eig(K);  // eigenvalues ascending
    const Eigen::Vector4d q = eig.eigenvectors().col(3);          // seed 004 eq. 6.27-6.29
    const double lambda = eig.eigenvalues()(3);

    WahbaSolution sol;
    sol.ok = true;
    sol.q_ib = Quat(q(3), q(0), q(1), q(2));  // [q_v; q_4] of A = q_ib (wahba_math.hpp)
    sol.loss = p.weight_sum * std::max(0.0, 1.0 - lambda);  // seed 004 eq. 6.30, scaled by W
    sol.cov_body = fisherCovariance(p);
    return sol;
  }
};

}  // namespace

std::unique_ptr<WahbaSolver> makeQMethodSolver() { return std::make_unique<QMethodSolver>(); }

}  // namespace st

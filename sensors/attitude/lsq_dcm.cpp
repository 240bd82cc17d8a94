// Least-squares DCM (seed 001 sec. III.A, eqs. 25-31): the nine elements of the attitude
// matrix as free unknowns of the linear model r_k = M b_k (eq. 26-30; here M = R_ib = A^T,
// so the seed's unknown x holds the rows of M), solved by the normal equations (eq. 31) with
// the weights a_k = 1/sigma_k^2. The 27 x 9 normal matrix is block-diagonal, I3 (x) G with
// G = sum a_k b_k b_k^T, so M = (sum a_k r_k b_k^T) G^-1 (one 3x3 solve for the three rows).
//
// Unit vectors need three linearly independent b_k: with two, or all b_k in one plane
// through the origin, G is singular and the problem is refused (the optimal solvers need
// only two). The least-squares M is not orthogonal in general (it fits 9 numbers to what is
// a 3-parameter rotation), so the attitude reported is its nearest rotation (orthogonal
// Procrustes: M = U S V^T -> U diag(1, 1, det U V^T) V^T). The result is not Wahba's optimum:
// the fit spends the noise on 9 numbers, and the projection does not undo that (measured with
// 8 vectors: RMS error 1.26x the q-method's in a 15 deg field, 1.14x over the whole sky;
// tests/attitude/test_lsq_dcm.cpp).
//
// Covariance (first order, QMM noise e_k on b_k): M = R_ib (I + F) with
// F = -sum_k a_k e_k c_k^T, c_k = G^-1 b_k, and the polar factor turns by
// phi = vee((F - F^T) / 2) = -1/2 sum_k a_k c_k x e_k, so
//   P = 1/4 sum_k a_k [c_k]x (I - b_k b_k^T) [c_k]x^T
// (equal to the optimal Fisher covariance for three orthogonal vectors, larger otherwise).
#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <Eigen/SVD>
#include <cmath>

#include "sensors/attitude/wahba_math.hpp"

namespace st {
namespace {

/// G's smallest / largest eigenvalue below this: the vectors are too close to coplanar for
/// the 3x3 solve (relative error ~ eps / ratio) to stay below 1e-3 of the statistical error.
constexpr double kMinEigenRatio = 1e-8;

/// The normal equations' pieces: G = sum a_k b_k b_k^T, C = sum a_k r_k b_k^T (a_k = 1/sigma^2).
void normalSums(const std::vector<VectorObservation>& obs, Mat3& G, Mat3& C) {
  G.setZero();
  C.setZero();
  for (const VectorObservation& o : obs) {
    const double a = 1.0 / (o.sigma * o.sigma);
    G.noalias() += a * o.b * o.b.transpose();
    C.noalias() += a * o.r * o.b.transpose();
  }
}

class LsqDcmSolver final : public WahbaSolver {
 public:
  std::string name() const override { return "lsq"; }
  bool minimisesLoss() const override { return false; }  // unconstrained fit + projection
  int minVectors() const override { return 3; }

 private:
  WahbaSolution doSolve(const std::vector<VectorObservation>& obs) const override {
    Mat3 G, C;
    normalSums(obs, G, C);
    WahbaSolution sol;
    Eigen::SelfAdjointEigenSolver<Mat3> eig(G);
    const Vec3 ev = eig.eigenvalues();  // ascending
    if (!(ev(0) > kMinEigenRatio * ev(2))) {
      sol.reason = "lsq: the measured vectors are (nearly) collinear or coplanar; the "
                   "least-squares DCM needs 3 linearly independent vectors";
      return sol;
    }
    const Mat3 Ginv = eig.eigenvectors() * ev.cwiseInverse().asDiagonal() *
                      eig.eigenvectors().transpose();
    const Mat3 M = C * Ginv;  // seed 001 eq. 31, all three rows at once
    Eigen::JacobiSVD<Mat3> svd(M, Eigen::ComputeFullU | Eigen::ComputeFullV);
    Mat3 D = Mat3::Identity();
    D(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0 ? -1.0 : 1.0;
    const Mat3 R_ib = svd.matrixU() * D * svd.matrixV().transpose();
    Mat3 P = Mat3::Zero();
    for (const VectorObservation& o : obs) {
      const double a = 1.0 / (o.sigma * o.sigma);
      const Mat3 Sc = skew(Ginv * o.b);
      P.noalias() += 0.25 * a * Sc * (Mat3::Identity() - o.b * o.b.transpose()) * Sc.transpose();
    }
    sol.ok = true;
    sol.q_ib = canonical(Quat(R_ib));
    sol.loss = wahbaLoss(obs, sol.q_ib);  // of the projected attitude, not of M
    sol.cov_body = P;
    return sol;
  }
};

}  // namespace

std::unique_ptr<WahbaSolver> makeLsqDcmSolver() { return std::make_unique<LsqDcmSolver>(); }

/// Non-orthogonality of the unprojected least-squares matrix, |M^T M - I|_F (for the tests
/// and reports: seed 001's eq. 31 returns M, not a rotation).
double lsqDcmOrthogonalityDefect(const std::vector<VectorObservation>& obs) {
  Mat3 G, C;
  normalSums(obs, G, C);
  const Mat3 M = C * G.inverse();
  return (M.transpose() * M - Mat3::Identity()).norm();
}

}  // namespace st

#include "sensors/attitude/wahba_math.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace st::wahba_detail {

Problem buildProblem(const std::vector<VectorObservation>& obs) {
  Problem p;
  for (const VectorObservation& o : obs) p.weight_sum += 1.0 / (o.sigma * o.sigma);
  p.sigma_tot2 = 1.0 / p.weight_sum;  // seed 004 eq. 6.36
  for (const VectorObservation& o : obs) {
    const double a = p.sigma_tot2 / (o.sigma * o.sigma);  // seed 004 eq. 6.35
    p.B.noalias() += a * o.b * o.r.transpose();           // seed 004 eq. 6.38
    p.Mb.noalias() += a * o.b * o.b.transpose();
  }
  return p;
}

Mat3 fisherCovariance(const Problem& p) {
  // Fisher information of the QMM: H_k = [b_k x], R_k^+ = (I - b b^T)/sigma_k^2, so
  // sum H^T R^+ H = sum (I - b b^T)/sigma_k^2 = (I - Mb)/sigma_tot^2 (seed 004 eq. 6.17).
  const Mat3 info = Mat3::Identity() - p.Mb;
  return p.sigma_tot2 * info.inverse();
}

KTerms kTerms(const Mat3& B) {
  KTerms k;
  k.S = B + B.transpose();                                              // seed 001 eq. 43
  k.z = Vec3(B(1, 2) - B(2, 1), B(2, 0) - B(0, 2), B(0, 1) - B(1, 0));  // seed 001 eq. 44
  k.sigma = B.trace();                                                  // seed 001 eq. 45
  return k;
}

LambdaRoot lambdaMaxQuest(const KTerms& k) {
  // Shuster & Oh (1981) characteristic equation of K, coefficients from S, z, sigma:
  const double kappa = adjugate(k.S).trace();
  const double delta = k.S.determinant();
  const Vec3 Sz = k.S * k.z;
  const double a = k.sigma * k.sigma - kappa;
  const double b = k.sigma * k.sigma + k.z.squaredNorm();
  const double c = delta + k.z.dot(Sz);
  const double d = Sz.squaredNorm();  // z^T S^2 z
  const double c0 = a * b + c * k.sigma - d;
  // Newton from lambda = sum a_k = 1 >= lambda_max: the quartic is increasing and convex to
  // the right of its largest root, so the iterates decrease monotonically onto it.
  LambdaRoot root;
  double& lambda = root.lambda;
  for (int it = 0; it < 100; ++it) {
    const double l2 = lambda * lambda;
    const double f = (l2 - (a + b)) * l2 - c * lambda + c0;
    const double df = 4.0 * l2 * lambda - 2.0 * (a + b) * lambda - c;
    if (!(df > 0)) break;  // at a (numerically) double root: lambda is as good as it gets
    const double step = f / df;
    lambda -= step;
    if (std::abs(step) < 1e-16) break;
  }
  const double l2 = lambda * lambda;
  root.slope = 4.0 * l2 * lambda - 2.0 * (a + b) * lambda - c;
  return root;
}

double eigenvectorErrorBound(const KTerms& k, const Quat& q_ib, double slope) {
  const Eigen::Vector4d q(q_ib.x(), q_ib.y(), q_ib.z(), q_ib.w());  // [q_v; q_4]
  Eigen::Vector4d Kq;
  Kq.head<3>() = k.S * q.head<3>() - k.sigma * q.head<3>() + k.z * q(3);
  Kq(3) = k.z.dot(q.head<3>()) + k.sigma * q(3);
  const double rho = q.dot(Kq) / q.squaredNorm();
  const double residual = (Kq - rho * q).norm() / q.norm();
  if (!(slope > 0)) return std::numeric_limits<double>::infinity();
  return 2.0 * residual / (0.25 * slope);
}

std::string illConditionedReason(const std::string& solver, double error_bound) {
  std::ostringstream os;
  os << solver << ": vectors nearly collinear, characteristic-equation root too ill-conditioned"
     << " (error bound " << error_bound << " rad); use qmethod or svd";
  return os.str();
}

Mat3 adjugate(const Mat3& M) {
  // Columns are cross products of rows: row_i . (row_j x row_k) = det M for (i,j,k) cyclic.
  Mat3 adj;
  adj.col(0) = M.row(1).transpose().cross(M.row(2).transpose());
  adj.col(1) = M.row(2).transpose().cross(M.row(0).transpose());
  adj.col(2) = M.row(0).transpose().cross(M.row(1).transpose());
  return adj;
}

Mat3 turnReference(const Mat3& B, int axis) {
  if (axis < 0 || axis > 2) return B;
  Mat3 out = -B;  // D = diag(+-1) with +1 on `axis`: B' = B D negates the other two columns
  out.col(axis) = B.col(axis);
  return out;
}

Quat undoTurn(const Quat& q_ib_turned, int axis) {
  if (axis < 0 || axis > 2) return q_ib_turned;
  // r' = D r  =>  R'_ib = D R_ib  =>  R_ib = D R'_ib (D = D^T = D^-1), q_D = (0, e_axis).
  Quat q_D(0, 0, 0, 0);
  q_D.vec()(axis) = 1.0;
  return q_D * q_ib_turned;
}

Quat quatFromAttitudeMatrix(const Mat3& A) {
  const Mat3 R_ib = A.transpose();
  return canonical(Quat(R_ib));  // Eigen's branch on the largest diagonal term: accurate near pi
}

}  // namespace st::wahba_detail

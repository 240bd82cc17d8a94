/// @file wahba_math.hpp
/// Internal to sensors/attitude: the quantities every Wahba solver shares (attitude profile
/// matrix B, Davenport's K terms, the characteristic-equation root, the Fisher covariance,
/// reference-frame rotations by 180 deg).
///
/// Notation of the seeds: the attitude matrix A = R_ib^T maps inertial to body, b_k = A r_k.
/// Shuster's quaternion [q_v; q_4] of A, with K as in seed 001 eq. 42-45, has the same four
/// numbers as our Hamilton q_ib = (w = q_4, x, y, z = q_v)  (A(q) = R_Hamilton(q)^T).
#pragma once
#include <memory>
#include <string>
#include <vector>

#include "sensors/attitude/wahba.hpp"

namespace st::wahba_detail {

/// Weighted sums over the observations with weights normalised to sum 1.
struct Problem {
  double weight_sum = 0;   ///< W = sum 1/sigma_k^2 [rad^-2]
  double sigma_tot2 = 0;   ///< 1/W [rad^2] (seed 004 eq. 6.36)
  Mat3 B = Mat3::Zero();   ///< sum a_k b_k r_k^T, a_k = sigma_tot^2/sigma_k^2 (seed 004 eq. 6.38)
  Mat3 Mb = Mat3::Zero();  ///< sum a_k b_k b_k^T
};
Problem buildProblem(const std::vector<VectorObservation>& obs);

/// P = sigma_tot^2 (I - sum a_k b_k b_k^T)^-1: inverse Fisher information of the QMM in the
/// body frame (seed 004 eq. 6.17; eq. 6.34 times 4 for dtheta instead of the quaternion part).
Mat3 fisherCovariance(const Problem& p);

/// Davenport's K = [[S - sigma I, z], [z^T, sigma]] pieces (seed 001 eq. 42-45).
struct KTerms {
  Mat3 S;        ///< B + B^T
  Vec3 z;        ///< sum a_k b_k x r_k = (B23 - B32, B31 - B13, B12 - B21)
  double sigma;  ///< trace B
};
KTerms kTerms(const Mat3& B);

/// Largest eigenvalue of K by Newton's method on Shuster's characteristic equation
/// lambda^4 - (a+b) lambda^2 - c lambda + (ab + c sigma - d) = 0, started at sum a_k = 1.
struct LambdaRoot {
  double lambda = 1;  ///< lambda_max
  double slope = 0;   ///< f'(lambda_max) = product of the gaps to the other three eigenvalues
};
LambdaRoot lambdaMaxQuest(const KTerms& k);

/// A posteriori error bound [rad] of a quaternion q claimed to be K's top eigenvector
/// (Davis-Kahan): sin(angle to the eigenvector) <= |K q - rho q| / gap with rho = q^T K q; the
/// gap to the next eigenvalue is >= slope / 4 because the other two gaps are <= 2 each (the
/// eigenvalues of K lie in [-1, 1] for weights summing to 1), and a rotation angle is twice the
/// quaternion angle. Large when the vectors are nearly collinear (two eigenvalues of K nearly
/// equal) and a characteristic-equation root cannot tell them apart.
double eigenvectorErrorBound(const KTerms& k, const Quat& q_ib, double slope);

/// QUEST and ESOQ-2 refuse (ok = false) when that bound exceeds this fraction of sigma_tot, the
/// smallest 1-sigma the covariance can report (I - Mb has eigenvalues <= 1): the numerical
/// error then stays negligible against the statistical one in every direction.
constexpr double kMaxRootErrorPerSigma = 1e-3;
std::string illConditionedReason(const std::string& solver, double error_bound);

/// Classical adjugate adj(M) (M adj(M) = det(M) I), defined also for singular M.
Mat3 adjugate(const Mat3& M);

/// Reference frame turned by 180 deg about axis `axis` (0, 1, 2; 3 = no turn): r' = D r with
/// D = diag(+-1), so B' = B D. The solution in that frame maps back by q_ib = q_D * q'_ib.
Mat3 turnReference(const Mat3& B, int axis);
Quat undoTurn(const Quat& q_ib_turned, int axis);

/// q_ib (canonical) from the seeds' attitude matrix A = R_ib^T.
Quat quatFromAttitudeMatrix(const Mat3& A);

}  // namespace st::wahba_detail

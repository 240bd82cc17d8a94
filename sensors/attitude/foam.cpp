// FOAM (Markley 1993): the optimal attitude matrix from B, det B and adj B without an SVD
// (seed 004 eq. 6.54-6.58). lambda_max = s1 + s2 + d s3 is the largest root of
//   (lambda^2 - |B|^2)^2 - 8 lambda det B - 4 |adj B|^2 = 0   (Frobenius norms),
// found by Newton's method from sum a_k = 1; then kappa = (lambda^2 - |B|^2)/2 and
// zeta = kappa lambda - det B give eq. 6.55 and 6.57 without the singular values.
#include <algorithm>
#include <cmath>

#include "sensors/attitude/wahba_math.hpp"

namespace st {
namespace {

class FoamSolver final : public WahbaSolver {
 public:
  std::string name() const override { return "foam"; }

 private:
  WahbaSolution doSolve(const std::vector<VectorObservation>& obs) const override {
    using namespace wahba_detail;
    const Problem p = buildProblem(obs);
    const Mat3& B = p.B;
    const double detB = B.determinant();
    const double B2 = B.squaredNorm();
    const Mat3 adjBt = adjugate(B.transpose());
    const double adj2 = adjBt.squaredNorm();
    double lambda = 1.0;  // >= lambda_max; the quartic is increasing and convex beyond its root
    for (int it = 0; it < 100; ++it) {
      const double u = lambda * lambda - B2;
      const double f = u * u - 8.0 * lambda * detB - 4.0 * adj2;
      const double df = 4.0 * lambda * u - 8.0 * detB;
      if (!(df > 0)) break;
      const double step = f / df;
      lambda -= step;
      if (std::abs(step) < 1e-16) break;
    }
    const double kappa = 0.5 * (lambda * lambda - B2);  // eq. 6.55
    const double zeta = kappa * lambda - detB;          // eq. 6.57
    const Mat3 BBt = B * B.transpose();
    const Mat3 A = ((kappa + B2) * B + lambda * adjBt - BBt * B) / zeta;  // eq. 6.54

    WahbaSolution sol;
    sol.ok = true;
    sol.q_ib = quatFromAttitudeMatrix(A);
    sol.loss = p.weight_sum * std::max(0.0, 1.0 - lambda);
    // eq. 6.58 with normalised weights; B B^T = U S^2 U^T is body-frame.
    sol.cov_body = p.sigma_tot2 * lambda * (kappa * Mat3::Identity() + BBt) / zeta;
    return sol;
  }
};

}  // namespace

std::unique_ptr<WahbaSolver> makeFoamSolver() { return std::make_unique<FoamSolver>(); }

}  // namespace st

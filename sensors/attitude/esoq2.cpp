// ESOQ-2 (Mortari 1997; seed 002 §"attitude estimator", ref. [20] with the improvements [22]).
// With q = [e sin(phi/2); cos(phi/2)], the 4th row of K q = lambda q gives
//   (lambda - sigma) cos(phi/2) = z^T e sin(phi/2),
// and substituting into the first three rows leaves the 3x3 problem M e = 0 with
//   M = (lambda - sigma) (S - (lambda + sigma) I) + z z^T   (symmetric, rank 2),
// so the rotation axis e is any non-zero column of adj(M) and q ~ [(lambda - sigma) e; z^T e].
// This is singular at zero rotation (M = 0); as in Markley's ESOQ2.1, the reference frame is
// first turned by 180 deg about the axis picked by min(B11, B22, B33, tr B), so the solved
// rotation is far from the identity. lambda_max comes from QUEST's characteristic equation.
#include <algorithm>
#include <cmath>

#include "sensors/attitude/wahba_math.hpp"

namespace st {
namespace {

class Esoq2Solver final : public WahbaSolver {
 public:
  std::string name() const override { return "esoq2"; }

 private:
  WahbaSolution doSolve(const std::vector<VectorObservation>& obs) const override {
    using namespace wahba_detail;
    const Problem p = buildProblem(obs);
    const KTerms k0 = kTerms(p.B);
    const LambdaRoot root = lambdaMaxQuest(k0);
    const double lambda = root.lambda;
    WahbaSolution sol;

    int axis = 3;  // 3 = no turn
    double smallest = p.B.trace();
    for (int i = 0; i < 3; ++i) {
      if (p.B(i, i) < smallest) {
        smallest = p.B(i, i);
        axis = i;
      }
    }
    const KTerms k = kTerms(turnReference(p.B, axis));
    const double lms = lambda - k.sigma;
    const Mat3 M = lms * (k.S - (lambda + k.sigma) * Mat3::Identity()) + k.z * k.z.transpose();
    const Mat3 adjM = adjugate(M);  // = c e e^T: every column is along e
    int col = 0;
    adjM.diagonal().cwiseAbs().maxCoeff(&col);  // |adj_ii| = |c| e_i^2: the longest column
    const Vec3 e = adjM.col(col);
    const Vec3 v = lms * e;
    const Quat q_turned(k.z.dot(e), v.x(), v.y(), v.z());

    sol.q_ib = undoTurn(q_turned.normalized(), axis);
    const double error_bound = eigenvectorErrorBound(k0, sol.q_ib, root.slope);
    if (!(error_bound <= kMaxRootErrorPerSigma * std::sqrt(p.sigma_tot2))) {
      sol.reason = illConditionedReason(name(), error_bound);
      return sol;
    }
    sol.ok = true;
    sol.loss = p.weight_sum * std::max(0.0, 1.0 - lambda);  // seed 004 eq. 6.30, scaled by W
    sol.cov_body = fisherCovariance(p);
    return sol;
  }
};

}  // namespace

std::unique_ptr<WahbaSolver> makeEsoq2Solver() { return std::make_unique<Esoq2Solver>(); }

}  // namespace st

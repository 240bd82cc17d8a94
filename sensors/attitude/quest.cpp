// QUEST (Shuster): lambda_max by Newton's method on K's characteristic equation, then the
// quaternion in closed form from Gibbs' vector y = ((lambda + sigma) I - S)^-1 z (seed 004
// eq. 6.32/6.33, seed 001 §III.C), written without the inverse as q ~ [adj(rho I - S) z;
// det(rho I - S)], rho = lambda + sigma.
//
// Near 180 deg that determinant gamma and the vector part both vanish. Shuster's method of
// sequential rotations solves the problem in a reference frame turned by 180 deg about x, y or
// z instead. Since K' = T K T^T has the same characteristic polynomial f, the frame-k gamma is
// f'(lambda) q_k^2 (q_k the k-th quaternion component in the original frame, q_4 for the
// original frame): the largest gamma picks the best-conditioned frame (|q_k| >= 1/2) directly.
#include <algorithm>
#include <cmath>

#include "sensors/attitude/wahba_math.hpp"

namespace st {
namespace {

class QuestSolver final : public WahbaSolver {
 public:
  std::string name() const override { return "quest"; }

 private:
  WahbaSolution doSolve(const std::vector<VectorObservation>& obs) const override {
    using namespace wahba_detail;
    const Problem p = buildProblem(obs);
    const KTerms k0 = kTerms(p.B);
    const LambdaRoot root = lambdaMaxQuest(k0);
    const double lambda = root.lambda;
    WahbaSolution sol;

    // Candidate frames: 3 = as given, 0/1/2 = reference turned by 180 deg about x/y/z.
    int best_axis = 3;
    KTerms best = k0;
    double best_gamma = (((lambda + k0.sigma) * Mat3::Identity()) - k0.S).determinant();
    for (int axis = 0; axis < 3; ++axis) {
      const KTerms k = kTerms(turnReference(p.B, axis));
      const double gamma = (((lambda + k.sigma) * Mat3::Identity()) - k.S).determinant();
      if (std::abs(gamma) > std::abs(best_gamma)) {
        best_gamma = gamma;
        best_axis = axis;
        best = k;
      }
    }
    const Mat3 rhoI_S = (lambda + best.sigma) * Mat3::Identity() - best.S;  // seed 004 eq. 6.33
    const Vec3 x = adjugate(rhoI_S) * best.z;  // gamma * y: Gibbs vector times the determinant
    const Quat q_turned(best_gamma, x.x(), x.y(), x.z());  // seed 004 eq. 6.32 times gamma

    sol.q_ib = undoTurn(q_turned.normalized(), best_axis);
    const double error_bound = eigenvectorErrorBound(k0, sol.q_ib, root.slope);
    if (!(error_bound <= kMaxRootErrorPerSigma * std::sqrt(p.sigma_tot2))) {
      sol.reason = illConditionedReason(name(), error_bound);
      return sol;
    }
    sol.ok = true;
    sol.loss = p.weight_sum * std::max(0.0, 1.0 - lambda);  // seed 004 eq. 6.30, scaled by W
    sol.cov_body = fisherCovariance(p);                     // seed 004 eq. 6.34 (x4)
    return sol;
  }
};

}  // namespace

std::unique_ptr<WahbaSolver> makeQuestSolver() { return std::make_unique<QuestSolver>(); }

}  // namespace st

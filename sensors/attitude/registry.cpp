// The one table of Wahba solvers: names, help, CLI choices and factories come from here.
// A new solver: its own file defining `std::unique_ptr<WahbaSolver> makeXSolver()` in
// namespace st, plus ONE line below, X("name", makeXSolver, "help"), which declares the
// factory and lists it (common/family_registry.hpp says why not a self-registering object).
#include "common/family_registry.hpp"
#include "sensors/attitude/wahba.hpp"

// clang-format off
#define ST_WAHBA_SOLVERS(X)                                                                     \
  X("triad", makeTriadSolver, "TRIAD from the two most informative vectors (not optimal; Shuster & Oh covariance)") \
  X("qmethod", makeQMethodSolver, "Davenport's q-method: symmetric 4x4 eigen-decomposition of K (reference)") \
  X("quest", makeQuestSolver, "QUEST: Newton on K's characteristic equation, sequential rotations near 180 deg") \
  X("esoq2", makeEsoq2Solver, "ESOQ-2 (Mortari): rotation axis from the 3x3 null space, 180 deg frame turn") \
  X("svd", makeSvdSolver, "Markley's SVD of the attitude profile matrix B (most robust)")        \
  X("foam", makeFoamSolver, "FOAM (Markley): optimal matrix from B, det B and adj B without an SVD") \
  X("lsq", makeLsqDcmSolver, "least-squares DCM (seed 001 eq. 31): 9 free elements, then the nearest rotation (not optimal; needs 3 independent vectors)") \
  X("pad", makePadSolver, "Predictive Attitude Determination (seed 004 eq. 6.9-6.16): Gauss-Newton steps of the kinematic model error from TRIAD's attitude")
// clang-format on

namespace st {

#define ST_DECLARE_WAHBA_FACTORY(name, factory, help) WahbaSolver::Make factory;
ST_WAHBA_SOLVERS(ST_DECLARE_WAHBA_FACTORY)

namespace {

FamilyRegistry<WahbaSolver::Factory>& registry() {
  static FamilyRegistry<WahbaSolver::Factory> r("Wahba solver",
                                                {ST_WAHBA_SOLVERS(ST_FAMILY_TABLE_ENTRY)});
  return r;
}

}  // namespace

void WahbaSolver::registerMember(const std::string& name, const std::string& help,
                                 Factory make) {
  registry().add({name, help, make});
}

std::unique_ptr<WahbaSolver> WahbaSolver::create(const std::string& name, std::string* error) {
  return registry().create(name, error);
}

std::vector<std::string> WahbaSolver::names() { return registry().names(); }

std::string WahbaSolver::defaultName() { return "quest"; }

std::string WahbaSolver::help(const std::string& name) {
  const auto* m = registry().find(name);
  return m ? m->help : std::string();
}

}  // namespace st

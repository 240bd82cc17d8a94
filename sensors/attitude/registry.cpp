// The one table of Wahba solvers: names, help and factories come from here.
#include <sstream>

#include "sensors/attitude/wahba_math.hpp"

namespace st {
namespace {

struct Entry {
  const char* name;
  const char* help;
  std::unique_ptr<WahbaSolver> (*make)();
};

const Entry kSolvers[] = {
    {"triad", "TRIAD from the two most informative vectors (not optimal; Shuster & Oh covariance)",
     &makeTriadSolver},
    {"qmethod", "Davenport's q-method: symmetric 4x4 eigen-decomposition of K (reference)",
     &makeQMethodSolver},
    {"quest", "QUEST: Newton on K's characteristic equation, sequential rotations near 180 deg",
     &makeQuestSolver},
    {"esoq2", "ESOQ-2 (Mortari): rotation axis from the 3x3 null space, 180 deg frame turn",
     &makeEsoq2Solver},
    {"svd", "Markley's SVD of the attitude profile matrix B (most robust)", &makeSvdSolver},
    {"foam", "FOAM (Markley): optimal matrix from B, det B and adj B without an SVD",
     &makeFoamSolver},
};

}  // namespace

std::unique_ptr<WahbaSolver> WahbaSolver::create(const std::string& name, std::string* error) {
  for (const Entry& e : kSolvers)
    if (name == e.name) return e.make();
  if (error) {
    std::ostringstream os;
    os << "unknown Wahba solver '" << name << "'; valid:";
    for (const Entry& e : kSolvers) os << ' ' << e.name;
    *error = os.str();
  }
  return nullptr;
}

std::vector<std::string> WahbaSolver::names() {
  std::vector<std::string> out;
  for (const Entry& e : kSolvers) out.emplace_back(e.name);
  return out;
}

std::string WahbaSolver::defaultName() { return "quest"; }

std::string WahbaSolver::help(const std::string& name) {
  for (const Entry& e : kSolvers)
    if (name == e.name) return e.help;
  return {};
}

}  // namespace st

// Shows that a Wahba solver compiled into an executable is one file and ONE registration
// line: "svd_in_test" (the SVD solver under another name, a trivial-but-valid member) is
// registered below, and the family's shared suite (test_wahba_solvers.cpp) runs every
// property on it as AllSolvers/WahbaSolverTest.*/svd_in_test without being edited.
#include "common/family_registry.hpp"
#include "sensors/attitude/wahba.hpp"

namespace st {
namespace {

class SvdInTest final : public WahbaSolver {
 public:
  std::string name() const override { return "svd_in_test"; }

 private:
  WahbaSolution doSolve(const std::vector<VectorObservation>& obs) const override {
    return svd_->solve(obs);
  }
  std::unique_ptr<WahbaSolver> svd_ = WahbaSolver::create("svd");
};

std::unique_ptr<WahbaSolver> makeSvdInTest() { return std::make_unique<SvdInTest>(); }

}  // namespace
}  // namespace st

ST_REGISTER_FAMILY_MEMBER(st::WahbaSolver, "svd_in_test", "the SVD solver, registered by a test",
                          &st::makeSvdInTest);

// The shared suite of the Wahba family: every solver in the registry (TEST_P over
// WahbaSolver::names(), cases named by solver), including solvers registered by a test file
// of this executable, gets the properties of tests/support/wahba_test_utils.hpp.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "sensors/attitude/wahba.hpp"
#include "tests/support/wahba_test_utils.hpp"

namespace st {
namespace {

class WahbaSolverTest : public ::testing::TestWithParam<std::string> {
 protected:
  void SetUp() override {
    std::string error;
    solver_ = WahbaSolver::create(GetParam(), &error);
    ASSERT_NE(solver_, nullptr) << error;
  }
  std::unique_ptr<WahbaSolver> solver_;
};

TEST_P(WahbaSolverTest, RegistryRoundTrip) {
  EXPECT_EQ(solver_->name(), GetParam());
  EXPECT_FALSE(WahbaSolver::help(GetParam()).empty());
}

TEST_P(WahbaSolverTest, NoiselessRecoversTruthAndAgrees) {
  test::expectNoiselessRecovery(*solver_);
}

TEST_P(WahbaSolverTest, NearCollinearIsGraceful) { test::expectNearCollinearGraceful(*solver_); }

TEST_P(WahbaSolverTest, NeesOfReportedCovarianceInChiSquareBand) {
  test::expectNeesInChiSquareBand(*solver_);
}

TEST_P(WahbaSolverTest, LossIsWahbaLossAtSolution) { test::expectLossIsWahbaLoss(*solver_); }

TEST_P(WahbaSolverTest, DegenerateInputGivesReasonNotCrash) {
  test::expectDegenerateInputRefused(*solver_);
}

INSTANTIATE_TEST_SUITE_P(AllSolvers, WahbaSolverTest, ::testing::ValuesIn(WahbaSolver::names()),
                         [](const ::testing::TestParamInfo<std::string>& info) {
                           return info.param;
                         });

TEST(WahbaRegistry, UnknownNameListsTheValidOnes) {
  std::string error;
  EXPECT_EQ(WahbaSolver::create("nope", &error), nullptr);
  for (const std::string& n : WahbaSolver::names()) EXPECT_NE(error.find(n), std::string::npos);
  EXPECT_NE(WahbaSolver::create(WahbaSolver::defaultName()), nullptr);
}

// The library's own solvers come first, in table order (the CLI lists them so); members
// registered by an executable follow.
TEST(WahbaRegistry, LibraryTableFirstInOrder) {
  const std::vector<std::string> lib = {"triad", "qmethod", "quest", "esoq2", "svd", "foam", "lsq", "pad"};
  const std::vector<std::string> all = WahbaSolver::names();
  ASSERT_GE(all.size(), lib.size());
  EXPECT_EQ(std::vector<std::string>(all.begin(), all.begin() + lib.size()), lib);
}

}  // namespace
}  // namespace st

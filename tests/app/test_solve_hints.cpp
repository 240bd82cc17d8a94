// solve-field's habits in `solve` (issue 21 item 10): a position hint accepts only a
// boresight inside its circle; --cpulimit stops the search and says so.
#include <gtest/gtest.h>

#include "tests/app/solve_cli_util.hpp"

namespace st {
namespace {

// The tetra3 README's field centre of this frame: RA 230.7, Dec +11.0 deg.
const std::string kFrame = "--fov-deg 11.4 " + test::tetra3Frame();

TEST(SolveHints, HintNearTheTruthSolves) {
  const auto r = test::solveJson("--ra 231.5 --dec 10 --radius 2 " + kFrame);
  ASSERT_EQ(r.rc, 0) << r.stdout_text;
  EXPECT_NEAR(r.json.at("ra_deg").get<double>(), 230.7, 0.1);
}

TEST(SolveHints, HintFarFromTheTruthIsNotSolved) {
  // 1.9 deg from the truth with a 1.5 deg radius: the right stars, the wrong place.
  const auto r = test::solveJson("--ra 230.7 --dec 12.9 --radius 1.5 " + kFrame);
  EXPECT_EQ(r.rc, 1) << r.stdout_text;
  ASSERT_FALSE(r.json.is_null()) << r.stdout_text;
  EXPECT_EQ(r.json.at("solved"), false);
  EXPECT_NE(r.json.at("reason").get<std::string>().find("position hint"), std::string::npos)
      << r.stdout_text;
  const auto far = test::solveJson("--ra 50 --dec -40 --radius 5 " + kFrame);
  EXPECT_EQ(far.rc, 1) << far.stdout_text;
}

TEST(SolveHints, AnIncompleteOrBadHintIsAnInputError) {
  auto r = test::solveJson("--ra 230 --dec 11 " + kFrame);
  EXPECT_EQ(r.rc, 2) << r.stdout_text;
  EXPECT_NE(r.json.at("error").get<std::string>().find("--radius"), std::string::npos);
  r = test::solveJson("--ra 230 --dec 95 --radius 3 " + kFrame);
  EXPECT_EQ(r.rc, 2) << r.stdout_text;
  EXPECT_NE(r.json.at("error").get<std::string>().find("--dec"), std::string::npos);
}

TEST(SolveHints, CpuLimitStopsTheFovSearch) {
  // The FOV search over 5..30 deg takes seconds; building the database alone takes longer
  // than 1 ms, so the search stops before its first try.
  const auto r = test::solveJson("--cpulimit 0.001 " + test::tetra3Frame());
  EXPECT_EQ(r.rc, 1) << r.stdout_text;
  ASSERT_FALSE(r.json.is_null()) << r.stdout_text;
  EXPECT_EQ(r.json.at("cpu_limit_reached"), true);
  EXPECT_NE(r.json.at("reason").get<std::string>().find("cpu limit reached"), std::string::npos)
      << r.stdout_text;
  EXPECT_EQ(r.json.at("parities_tried"), 1);  // the mirrored retry is not started either
}

TEST(SolveHints, GenerousCpuLimitStillSolves) {
  const auto r = test::solveJson("--cpulimit 600 " + kFrame);
  EXPECT_EQ(r.rc, 0) << r.stdout_text;
}

}  // namespace
}  // namespace st

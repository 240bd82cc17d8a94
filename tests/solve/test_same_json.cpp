// One plate solver for every caller: `startracker solve --json`, st::api::solveFile and
// st::api::solve (an image in memory) give the same JSON object for a frame, apart from the
// timings, on the eight real frames and on a star list.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "imageio/image_file.hpp"
#include "include/startracker/startracker.hpp"
#include "tests/app/solve_cli_util.hpp"
#include "tests/support/test_paths.hpp"

namespace st {
namespace {

nlohmann::json withoutTimings(nlohmann::json j) {
  j.erase("timing_ms");
  return j;
}

nlohmann::json apiJson(const api::SolveResult& r) { return nlohmann::json::parse(r.json.dump()); }

class SameJson : public ::testing::TestWithParam<std::string> {};

TEST_P(SameJson, CommandLineAndLibraryAgree) {
  const std::string frame = test::tetra3Frame(GetParam());
  const test::SolveRun cli = test::solveJson("--no-cache --fov-deg 11.4 " + test::shellQuote(frame));
  ASSERT_EQ(cli.rc, 0) << cli.stdout_text;
  ASSERT_TRUE(cli.json.value("solved", false));

  api::SolveOptions o;
  o.fov_deg = 11.4;
  o.no_cache = true;
  const api::SolveResult file = api::solveFile(frame, o);
  ASSERT_TRUE(file.solved);
  EXPECT_EQ(withoutTimings(apiJson(file)), withoutTimings(cli.json));

  // In memory: the epoch and name are the caller's to give.
  o.epoch_jyear = cli.json["epoch_jyear"].get<double>();
  o.name = frame;
  const api::SolveResult mem = api::solve(imageio::loadImage(frame).image, o);
  nlohmann::json expected = withoutTimings(cli.json);
  expected["epoch_source"] = "--epoch";  // given, not read from the file name
  std::string db_source = expected["database"];
  db_source.replace(db_source.find("epoch from file name"), 20, "epoch from --epoch");
  expected["database"] = db_source;
  EXPECT_EQ(withoutTimings(apiJson(mem)), expected);
}

INSTANTIATE_TEST_SUITE_P(Tetra3, SameJson,
                         ::testing::Values("2019-07-29T204726_Alt40_Azi-135_Try1",
                                           "2019-07-29T204726_Alt40_Azi-45_Try1",
                                           "2019-07-29T204726_Alt40_Azi135_Try1",
                                           "2019-07-29T204726_Alt40_Azi45_Try1",
                                           "2019-07-29T204726_Alt60_Azi-135_Try1",
                                           "2019-07-29T204726_Alt60_Azi-45_Try1",
                                           "2019-07-29T204726_Alt60_Azi135_Try1",
                                           "2019-07-29T204726_Alt60_Azi45_Try1"));

TEST(SameJson, StarList) {
  // The stars the command line detected, as a star list (CSV x,y,flux).
  const std::string frame = test::tetra3Frame();
  const test::SolveRun cli = test::solveJson("--no-cache --fov-deg 11.4 " + test::shellQuote(frame));
  ASSERT_EQ(cli.rc, 0);
  const std::string list = test::makeTempDir("same_json") + "/2019-07-29T204726_stars.csv";
  {
    std::ofstream f(list);
    f << "x,y,flux\n";
    double flux = 1e6;
    for (const auto& s : cli.json["stars"]) f << s["x"].get<double>() << "," << s["y"].get<double>() << "," << (flux *= 0.9) << "\n";
  }
  const test::SolveRun from_list = test::solveJson("--no-cache --fov-deg 11.4 --width 1024 --height 768 " +
                                                   test::shellQuote(list));
  ASSERT_EQ(from_list.rc, 0) << from_list.stdout_text;
  api::SolveOptions o;
  o.fov_deg = 11.4;
  o.no_cache = true;
  o.width = 1024;
  o.height = 768;
  const api::SolveResult r = api::solveFile(list, o);
  ASSERT_TRUE(r.solved);
  EXPECT_EQ(withoutTimings(apiJson(r)), withoutTimings(from_list.json));
}

}  // namespace
}  // namespace st

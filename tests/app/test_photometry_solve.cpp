// `solve --json` reports photometry (sensors/identify/photometry.hpp): the fitted zero point,
// colour term and scatter, and per identified star its catalog V, B-V, instrument and fitted
// magnitude and residual; every fitted magnitude agrees with V within 3 x the scatter except
// the clipped ones.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "tests/app/solve_cli_util.hpp"

namespace st::test {
namespace {

TEST(SolvePhotometry, JsonHasZeroPointColourTermAndPerStarMagnitudes) {
  const SolveRun r =
      solveJson("--fov-deg 11.4 " + shellQuote(tetra3Frame("2019-07-29T204726_Alt40_Azi45_Try1")));
  ASSERT_EQ(r.rc, 0) << r.stdout_text;
  const auto& p = r.json.at("photometry");
  ASSERT_TRUE(p.at("fitted").get<bool>()) << p.dump();
  const double scatter = p.at("scatter_mag").get<double>();
  EXPECT_GT(scatter, 0.02);
  EXPECT_LT(scatter, 0.25);
  EXPECT_NEAR(p.at("zero_point").get<double>(), 16.5, 0.3);  // tests/identify: 16.54 +- 0.02
  ASSERT_FALSE(p.at("colour_term").is_null());                // Hipparcos has B-V
  EXPECT_GT(p.at("colour_term").get<double>(), 0.0);
  EXPECT_EQ(p.at("off_axis_exponent").get<double>(), 4.0);    // 11 deg cannot fit it
  EXPECT_FALSE(p.at("off_axis_exponent_fitted").get<bool>());
  int used = 0;
  for (const auto& s : r.json.at("stars")) {
    ASSERT_TRUE(s.contains("mag_fitted")) << s.dump();
    if (!s.at("photometry_used").get<bool>()) continue;
    ++used;
    const double v = s.at("mag").get<double>(), fit = s.at("mag_fitted").get<double>();
    EXPECT_NEAR(v - fit, s.at("mag_residual").get<double>(), 1e-9);
    EXPECT_LT(std::abs(v - fit), 3 * scatter) << s.dump();
  }
  EXPECT_EQ(used, p.at("stars_used").get<int>());
  EXPECT_GE(used, 30);
}

// The tie-break's key (sensors/mrpt/pipeline_ini.cpp, strict schema): printed with its value,
// a negative value is bad input naming the key (exit 2).
TEST(SolvePhotometry, LisMagnitudeSigmaKeyIsReadStrictly) {
  const std::string dir = makeTempDir("phot_ini");
  std::ifstream in(repoDir() + "/rawlogs/tracker.ini");
  std::stringstream ss;
  ss << in.rdbuf();
  std::string ini = ss.str();
  const auto at = ini.find("[pipeline]\n");
  ASSERT_NE(at, std::string::npos);
  const auto write = [&](const std::string& value) {
    std::string t = ini;
    t.insert(at + 11, "lis_magnitude_sigma = " + value + "\n");
    std::ofstream(dir + "/t.ini") << t;
    std::string out;
    const int rc = runCommand(startrackerExe() + " config " + dir + "/t.ini 2>&1", &out);
    return std::make_pair(rc, out);
  };
  const auto good = write("0.13");
  EXPECT_EQ(good.first, 0) << good.second;
  EXPECT_NE(good.second.find("lis_magnitude_sigma = 0.13"), std::string::npos) << good.second;
  const auto bad = write("-0.5");
  EXPECT_EQ(bad.first, 2) << bad.second;
  EXPECT_NE(bad.second.find("lis_magnitude_sigma"), std::string::npos) << bad.second;
  EXPECT_NE(bad.second.find("-0.5"), std::string::npos) << bad.second;
}

}  // namespace
}  // namespace st::test

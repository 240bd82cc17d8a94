// End-to-end: `startracker solve` as a user runs it, on a real frame and on bad input.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <regex>

#include "tests/app/solve_cli_util.hpp"
#include "tests/support/test_paths.hpp"

namespace st {
namespace {

std::string realFrame() {
  return test::tetra3ImageDir() + "/2019-07-29T204726_Alt40_Azi-135_Try1.tiff";
}

double jsonNumber(const std::string& json, const std::string& key) {
  const std::regex re("\"" + key + "\":\\s*(-?[0-9.eE+-]+)");
  std::smatch m;
  if (!std::regex_search(json, m, re)) return std::nan("");
  return std::stod(m[1]);
}

TEST(SolveCli, RealFrameJsonHasTheDocumentedKeysAndTheKnownField) {
  std::string out;
  const int rc = test::runCommand(test::startrackerExe() + " solve --fov-deg 11.4 --json '" +
                                      realFrame() + "' 2>/dev/null",
                                  &out);
  ASSERT_EQ(rc, 0) << out;
  for (const char* key : {"\"ra_deg\"", "\"dec_deg\"", "\"roll_deg\"", "\"q_ib\"", "\"covariance\"",
                          "\"stars\"", "\"timing_ms\""})
    EXPECT_NE(out.find(key), std::string::npos) << key << " missing in " << out;
  // The tetra3 README gives the field centre of this frame: RA 230.7, Dec +11.0 deg.
  EXPECT_NEAR(jsonNumber(out, "ra_deg"), 230.7, 0.1);
  EXPECT_NEAR(jsonNumber(out, "dec_deg"), 11.0, 0.1);
  EXPECT_GE(jsonNumber(out, "stars_matched"), 10);
}

TEST(SolveCli, FovSearchWithoutCameraSolvesToo) {
  std::string out;
  const int rc = test::runCommand(test::startrackerExe() + " solve --json '" + realFrame() + "'", &out);
  ASSERT_EQ(rc, 0) << out;
  EXPECT_NEAR(jsonNumber(out, "dec_deg"), 11.0, 0.1);
}

// The text report counts FOVs only when it searched them: with --fov-deg there is nothing to
// count ("0 FOV(s) tried" was printed before).
TEST(SolveCli, TextReportCountsFovsOnlyForASearch) {
  std::string with_fov, searched;
  ASSERT_EQ(test::runCommand(test::startrackerExe() + " solve --fov-deg 11.4 '" + realFrame() +
                                 "' 2>/dev/null", &with_fov), 0);
  EXPECT_EQ(with_fov.find("FOVs tried"), std::string::npos) << with_fov;
  EXPECT_EQ(with_fov.find("FOV(s)"), std::string::npos) << with_fov;
  ASSERT_EQ(test::runCommand(test::startrackerExe() + " solve '" + realFrame() + "' 2>/dev/null",
                             &searched), 0);
  EXPECT_TRUE(std::regex_search(searched, std::regex("[1-9][0-9]* FOVs tried"))) << searched;
}

// Issue 39: `--epoch 0` or `--epoch -1` was ignored (the file name's epoch used) while 999
// was refused deep in the database: every value outside a Julian year is refused at once,
// naming the flag, exit 2.
TEST(SolveCli, EpochOutsideAJulianYearIsRefusedNamingTheFlag) {
  for (const char* bad : {"0", "-1", "999", "nan"}) {
    std::string out;
    EXPECT_EQ(test::runCommand(test::startrackerExe() + " solve --fov-deg 11.4 --epoch " + bad +
                                   " '" + realFrame() + "'", &out),
              2) << bad << ": " << out;
    EXPECT_NE(out.find("--epoch"), std::string::npos) << bad << ": " << out;
  }
}

TEST(SolveCli, BlackFrameExitsOneWithAReason) {
  const std::string path = test::makeTempDir("solve") + "/black.png";
  cv::imwrite(path, cv::Mat::zeros(480, 640, CV_8UC1));
  std::string out;
  EXPECT_EQ(test::runCommand(test::startrackerExe() + " solve --fov-deg 10 " + path, &out), 1) << out;
  EXPECT_NE(out.find("stars"), std::string::npos) << out;
}

TEST(SolveCli, BadInputExitsTwoNamingTheFile) {
  std::string out;
  EXPECT_EQ(test::runCommand(test::startrackerExe() + " solve --fov-deg 10 /no/such/image.png", &out), 2)
      << out;
  EXPECT_NE(out.find("/no/such/image.png"), std::string::npos) << out;
  const std::string dir = test::makeTempDir("solvebad");
  std::ofstream(dir + "/garbage.png") << "not an image";
  EXPECT_EQ(test::runCommand(test::startrackerExe() + " solve --fov-deg 10 " + dir + "/garbage.png", &out), 2)
      << out;
  EXPECT_NE(out.find("garbage.png"), std::string::npos) << out;
  EXPECT_EQ(test::runCommand(test::startrackerExe() + " solve --camera " + dir +
                                 "/nocam.yaml " + realFrame(),
                             &out),
            2)
      << out;
}

TEST(SolveCli, JsonEscapesFileNamesWithQuotesAndBackslashes) {
  const std::string name = test::makeTempDir("solve_quote") + "/a \"quoted\" \\ name.tiff";
  std::ifstream src(realFrame(), std::ios::binary);
  std::ofstream(name, std::ios::binary) << src.rdbuf();
  const auto r = test::solveJson("--fov-deg 11.4 " + test::shellQuote(name));
  ASSERT_EQ(r.rc, 0) << r.stdout_text;
  ASSERT_FALSE(r.json.is_null()) << "not valid JSON: " << r.stdout_text;
  EXPECT_EQ(r.json.at("image"), name);
  // A not-solved answer carries the reason and the name, escaped too.
  const std::string black = test::makeTempDir("solve_quote") + "/black \"\\.png";
  cv::imwrite(black, cv::Mat::zeros(480, 640, CV_8UC1));
  const auto nr = test::solveJson("--fov-deg 10 " + test::shellQuote(black));
  EXPECT_EQ(nr.rc, 1) << nr.stdout_text;
  ASSERT_FALSE(nr.json.is_null()) << "not valid JSON: " << nr.stdout_text;
  EXPECT_EQ(nr.json.at("image"), black);
  EXPECT_EQ(nr.json.at("exit_code"), 1);
}

TEST(SolveCli, JsonInputErrorsPrintOneErrorObjectAndExitTwo) {
  const std::string dir = test::makeTempDir("solve_jsonerr");
  std::ofstream(dir + "/garbage \"x\".png") << "not an image";
  for (const std::string& args :
       {"--fov-deg 10 " + test::shellQuote(dir + "/garbage \"x\".png"),
        "--fov-deg 10 --database " + dir + "/none.db " + realFrame(),
        "--camera " + dir + "/nocam.yaml " + realFrame()}) {
    const auto r = test::solveJson(args);
    EXPECT_EQ(r.rc, 2) << args << ": " << r.stdout_text;
    ASSERT_FALSE(r.json.is_null()) << args << ": not one JSON object: " << r.stdout_text;
    EXPECT_EQ(r.json.at("solved"), false);
    EXPECT_EQ(r.json.at("exit_code"), 2);
    EXPECT_FALSE(r.json.at("error").get<std::string>().empty());
  }
}

TEST(SolveCli, AnnotateToABadPathFailsBeforeAnyWork) {
  const std::string dir = test::makeTempDir("solve_annot");
  std::ofstream(dir + "/file") << "a file, not a folder";
  std::string out;
  EXPECT_EQ(test::runCommand(test::startrackerExe() + " solve --annotate " + dir +
                                 "/file/out.png " + realFrame(), &out), 2) << out;
  EXPECT_NE(out.find("--annotate"), std::string::npos) << out;
  EXPECT_EQ(out.find("boresight"), std::string::npos) << "worked before failing: " << out;
  // Checked before anything is read: a missing image is not even noticed.
  EXPECT_EQ(test::runCommand(test::startrackerExe() + " solve --annotate " + dir +
                                 "/file/out.png /no/such/image.png", &out), 2) << out;
  EXPECT_NE(out.find("--annotate"), std::string::npos) << out;
  EXPECT_EQ(test::runCommand(test::startrackerExe() + " solve --annotate " + dir + "/out.txt " +
                                 realFrame(), &out), 2) << out;
  EXPECT_NE(out.find("out.txt"), std::string::npos) << out;
  EXPECT_EQ(out.find("boresight"), std::string::npos) << "worked before failing: " << out;
}

TEST(SolveCli, AnnotateWritesThePictureAfterPrintingTheSolution) {
  const std::string png = test::makeTempDir("solve_annot_ok") + "/new/folder/solved.png";
  std::string out;
  ASSERT_EQ(test::runCommand(test::startrackerExe() + " solve --fov-deg 11.4 --annotate " + png +
                                 " " + realFrame(), &out), 0) << out;
  EXPECT_NE(out.find("boresight"), std::string::npos) << out;
  const cv::Mat img = cv::imread(png);
  EXPECT_EQ(img.cols, 1024);
}

}  // namespace
}  // namespace st

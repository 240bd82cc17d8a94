// `solve` on mirrored images (issue 21 item 9): a left-right mirrored copy of a real frame
// solves with parity "flipped" to the frame's own attitude; a top-bottom mirror (a bottom-up
// FITS) to the same boresight with the roll turned by 180 deg; --parity fixes the parity.
#include <gtest/gtest.h>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "tests/app/solve_cli_util.hpp"

namespace st {
namespace {

std::string mirroredCopy(int flip_code, const std::string& name) {
  const cv::Mat img = cv::imread(test::tetra3Frame(), cv::IMREAD_UNCHANGED);
  EXPECT_FALSE(img.empty());
  cv::Mat flipped;
  cv::flip(img, flipped, flip_code);
  // The frame's date stays in the name: the epoch (from the file name) must be the same.
  const std::string path =
      test::makeTempDir("solve_parity") + "/2019-07-29T204726_" + name;
  EXPECT_TRUE(cv::imwrite(path, flipped));
  return path;
}

const std::string kCamera = "--fov-deg 11.4 ";

TEST(SolveParity, NormalFrameSolvesWithNormalParity) {
  const auto r = test::solveJson(kCamera + test::tetra3Frame());
  ASSERT_EQ(r.rc, 0) << r.stdout_text;
  EXPECT_EQ(r.json.at("parity"), "normal");
}

TEST(SolveParity, LeftRightMirrorGivesTheFramesOwnAttitude) {
  const auto ref = test::solveJson(kCamera + test::tetra3Frame());
  const auto flip = test::solveJson(kCamera + mirroredCopy(1, "mirror_lr.tiff"));
  ASSERT_EQ(ref.rc, 0) << ref.stdout_text;
  ASSERT_EQ(flip.rc, 0) << flip.stdout_text;
  EXPECT_EQ(flip.json.at("parity"), "flipped");
  // The same centroids un-mirrored: the same stars, so the same attitude to well within
  // the solve's 1-sigma (~5 arcsec cross-boresight, ~50 arcsec roll on this frame).
  EXPECT_LT(test::attitudeDifferenceArcsec(ref.json, flip.json), 2.0);
  EXPECT_EQ(flip.json.at("stars_matched"), ref.json.at("stars_matched"));
  // Matched stars are reported at their pixels in the mirrored image.
  const int w = cv::imread(test::tetra3Frame(), cv::IMREAD_UNCHANGED).cols;
  const auto& s0 = ref.json.at("stars")[0];
  bool found = false;
  for (const auto& s : flip.json.at("stars"))
    if (s.at("id") == s0.at("id")) {
      found = true;
      EXPECT_NEAR(s.at("x").get<double>(), (w - 1) - s0.at("x").get<double>(), 0.05);
      EXPECT_NEAR(s.at("y").get<double>(), s0.at("y").get<double>(), 0.05);
    }
  EXPECT_TRUE(found);
}

TEST(SolveParity, TopBottomMirrorGivesTheSameBoresightRolledHalfATurn) {
  const auto ref = test::solveJson(kCamera + test::tetra3Frame());
  const auto flip = test::solveJson(kCamera + mirroredCopy(0, "mirror_tb.tiff"));
  ASSERT_EQ(ref.rc, 0) << ref.stdout_text;
  ASSERT_EQ(flip.rc, 0) << flip.stdout_text;
  EXPECT_EQ(flip.json.at("parity"), "flipped");
  const RaDecRoll a{deg2rad(ref.json.at("ra_deg").get<double>()),
                    deg2rad(ref.json.at("dec_deg").get<double>()),
                    deg2rad(ref.json.at("roll_deg").get<double>()) + kPi};
  const Quat expected = attitudeFromRaDecRoll(a);
  EXPECT_LT(rad2arcsec(expected.angularDistance(test::quatOf(flip.json))), 2.0);
}

TEST(SolveParity, ParityFlagFixesIt) {
  const std::string mirrored = mirroredCopy(1, "mirror_fixed.tiff");
  auto r = test::solveJson(kCamera + "--parity normal " + mirrored);
  EXPECT_EQ(r.rc, 1) << r.stdout_text;
  EXPECT_EQ(r.json.at("parities_tried"), 1);
  r = test::solveJson(kCamera + "--parity flipped " + mirrored);
  ASSERT_EQ(r.rc, 0) << r.stdout_text;
  EXPECT_EQ(r.json.at("parity"), "flipped");
  r = test::solveJson(kCamera + "--parity flipped " + test::tetra3Frame());
  EXPECT_EQ(r.rc, 1) << r.stdout_text;
  std::string out;
  EXPECT_EQ(test::runCommand(test::startrackerExe() + " solve --parity sideways " +
                                 test::tetra3Frame(), &out), 2) << out;
  EXPECT_NE(out.find("--parity"), std::string::npos) << out;
}

}  // namespace
}  // namespace st

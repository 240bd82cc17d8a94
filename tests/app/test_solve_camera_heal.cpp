// A camera file written from a datasheet (focal length 0.5-2 % off, no distortion) on the
// eight real tetra3 frames: `solve --camera` solves every frame, its attitude within 30" of
// the solution with the exact focal length, and names the discrepancy (self-healing
// calibration, sensors/identify/camera_refine.hpp).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "tests/app/solve_cli_util.hpp"

namespace st {
namespace {

std::string writeCamera(const std::string& dir, double rel_error) {
  return test::writeTetra3Camera(dir + "/cam_" + std::to_string(rel_error) + ".yaml", rel_error);
}

class CameraHeal : public ::testing::TestWithParam<double> {};

TEST_P(CameraHeal, EveryFrameSolvesNearTheExactCameraAndTheErrorIsNamed) {
  const double err = GetParam();
  const std::string dir = test::makeTempDir("camera_heal");
  const std::string db = dir + "/tetra3.db";
  ASSERT_EQ(test::runCommand(test::startrackerExe() + " catalog build -q --fov-deg 11.43 "
                                 "--size 1024 768 --margin-deg 0.5 --epoch 2019.57 -o " + db +
                                 " 2>&1"),
            0);
  const std::string exact = writeCamera(dir, 0), off = writeCamera(dir, err);
  const auto files = test::tetra3Frames();
  ASSERT_EQ(files.size(), 8u);
  for (const std::string& f : files) {
    SCOPED_TRACE(f);
    const auto ref = test::solveJson("--database " + db + " --camera " + exact + " " + test::shellQuote(f));
    ASSERT_EQ(ref.rc, 0) << ref.stdout_text;
    const auto run = test::solveJson("--database " + db + " --camera " + off + " " + test::shellQuote(f));
    ASSERT_EQ(run.rc, 0) << run.stdout_text;
    EXPECT_LT(test::attitudeDifferenceArcsec(run.json, ref.json), 30.0);
    const std::string d = run.json.at("camera").at("discrepancy").get<std::string>();
    EXPECT_NE(d.find("focal length appears"), std::string::npos) << d;
    EXPECT_NE(d.find(err > 0 ? "shorter than" : "longer than"), std::string::npos) << d;
    // The fitted focal length is the exact one to within what the lens's distortion trades
    // with it (k1 is fitted with it; 0.2 % covers the frames' spread).
    EXPECT_NEAR(run.json.at("camera").at("fit").at("fx").get<double>() / test::kTetra3ExactFx, 1.0, 0.002);
  }
}

INSTANTIATE_TEST_SUITE_P(FocalErrors, CameraHeal, ::testing::Values(-0.02, -0.005, 0.005, 0.02),
                         [](const auto& info) { return test::permilleName(info.param); });

}  // namespace
}  // namespace st

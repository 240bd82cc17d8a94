// Camera model: projection round trips with distortion, FOV, file loading errors.
#include <gtest/gtest.h>

#include <fstream>
#include <mrpt/config/CConfigFileMemory.h>

#include "common/conventions.hpp"
#include "common/errors.hpp"
#include "sensors/camera/camera_model.hpp"
#include "tests/support/test_paths.hpp"
#include "sensors/mrpt/camera_ini.hpp"

namespace st {
namespace {

CameraModel distortedCamera() {
  return CameraModel(1024, 768, 2950.0, 2948.0, 515.3, 380.7,
                     Distortion{-0.12, 0.08, 4e-4, -3e-4, -0.02});
}

TEST(CameraModel, PixelVectorPixelRoundTripWithDistortion) {
  const CameraModel cam = distortedCamera();
  double worst = 0;
  for (double y = -0.5; y <= cam.height() - 0.5; y += 7.3)
    for (double x = -0.5; x <= cam.width() - 0.5; x += 9.1) {
      const Vec3 v = cam.pixelToVector({x, y});
      ASSERT_NEAR(v.norm(), 1.0, 1e-15);
      const auto px = cam.vectorToPixel(v);
      ASSERT_TRUE(px.has_value());
      worst = std::max(worst, (*px - Vec2(x, y)).norm());
    }
  EXPECT_LT(worst, 1e-9);
}

TEST(CameraModel, StrongDistortionStillRoundTrips) {
  const CameraModel cam(640, 480, 300, 300, 320, 240, Distortion{-0.3, 0.1, 1e-3, 1e-3, -0.01});
  for (double y = 0; y < 480; y += 20)
    for (double x = 0; x < 640; x += 20) {
      const auto px = cam.vectorToPixel(cam.pixelToVector({x, y}));
      EXPECT_LT((*px - Vec2(x, y)).norm(), 1e-9) << x << "," << y;
    }
}

TEST(CameraModel, FromFovGivesTheFov) {
  const CameraModel cam = CameraModel::fromFov(1024, 768, deg2rad(11.4));
  EXPECT_NEAR(rad2deg(cam.horizontalFov()), 11.4, 1e-9);
  EXPECT_NEAR(cam.cx(), 511.5, 1e-12);
  const auto centre = cam.vectorToPixel(Vec3::UnitZ());
  EXPECT_NEAR((*centre - Vec2(511.5, 383.5)).norm(), 0.0, 1e-12);
  EXPECT_TRUE(cam.isVectorInImage(Vec3::UnitZ()));
  EXPECT_FALSE(cam.isVectorInImage(Vec3(1, 0, 0.1)));
  EXPECT_FALSE(cam.vectorToPixel(Vec3(0, 0, -1)).has_value());
  for (const Vec3& c : cam.cornerVectors())
    EXPECT_NEAR(std::acos(c.z()), cam.halfDiagonalFov(), 1e-12);
}

TEST(CameraModel, PixelJacobianMatchesFiniteDifferences) {
  const CameraModel cam = distortedCamera();
  const Vec3 v = cam.pixelToVector({900, 100});
  const Mat2 J = cam.pixelJacobian(v);
  const double h = 1e-7;
  for (int k = 0; k < 2; ++k) {
    Vec3 vp = v / v.z(), vm = v / v.z();
    vp[k] += h;
    vm[k] -= h;
    const Vec2 d = (*cam.vectorToPixel(vp) - *cam.vectorToPixel(vm)) / (2 * h);
    EXPECT_NEAR(d.x(), J(0, k), 1e-3);
    EXPECT_NEAR(d.y(), J(1, k), 1e-3);
  }
}

TEST(CameraModel, YamlRoundTrip) {
  const std::string path = test::makeTempDir("cam") + "/cam.yaml";
  const CameraModel cam = distortedCamera();
  cam.saveYaml(path);
  const CameraModel back = CameraModel::loadYaml(path);
  EXPECT_EQ(back.width(), 1024);
  EXPECT_DOUBLE_EQ(back.fx(), cam.fx());
  EXPECT_DOUBLE_EQ(back.distortion().k3, cam.distortion().k3);
}

void writeFile(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

TEST(CameraModel, BadFilesGiveClearErrors) {
  const std::string dir = test::makeTempDir("badcam");
  auto expectError = [](const std::string& path, const std::string& needle) {
    try {
      CameraModel::loadYaml(path);
      ADD_FAILURE() << "no error for " << path;
    } catch (const InputError& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find(needle), std::string::npos) << msg;
      EXPECT_NE(msg.find(path), std::string::npos) << msg;
    }
  };
  expectError(dir + "/nope.yaml", "does not exist");
  writeFile(dir + "/missing.yaml",
            "%YAML:1.0\n---\nimage_width: 640\nimage_height: 480\n"
            "distortion_coefficients: !!opencv-matrix\n   rows: 1\n   cols: 5\n   dt: d\n"
            "   data: [0, 0, 0, 0, 0]\n");
  expectError(dir + "/missing.yaml", "camera_matrix");
  writeFile(dir + "/neg.yaml",
            "%YAML:1.0\n---\nimage_width: 640\nimage_height: 480\n"
            "camera_matrix: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n"
            "   data: [-500, 0, 320, 0, 500, 240, 0, 0, 1]\n"
            "distortion_coefficients: !!opencv-matrix\n   rows: 1\n   cols: 5\n   dt: d\n"
            "   data: [0, 0, 0, 0, 0]\n");
  expectError(dir + "/neg.yaml", "focal");
  writeFile(dir + "/garbage.yaml", "this is: [not a camera\n");
  expectError(dir + "/garbage.yaml", "garbage.yaml");
}

TEST(CameraModel, MrptIniSection) {
  mrpt::config::CConfigFileMemory cfg(
      "[CAM]\nresolution = [640 480]\ncx = 319.5\ncy = 239.5\nfx = 800\nfy = 801\n"
      "dist = [0.01 -0.02 0 0 0]\n");
  const CameraModel cam = loadCameraIni(cfg, "CAM");
  EXPECT_EQ(cam.height(), 480);
  EXPECT_DOUBLE_EQ(cam.fy(), 801);
  EXPECT_DOUBLE_EQ(cam.distortion().k2, -0.02);
  mrpt::config::CConfigFileMemory bad("[CAM]\nresolution = [640 480]\ncx = 1\ncy = 1\nfx = 800\n");
  try {
    loadCameraIni(bad, "CAM");
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("'fy'"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace st

#include <mrpt/img/TCamera.h>
namespace st {
namespace {
TEST(CameraModel, MrptTCameraRoundTrip) {
  const CameraModel cam(1024, 768, 2950.0, 2948.0, 515.3, 380.7, Distortion{-0.1, 0.05, 1e-4, 2e-4, 0.01});
  const CameraModel back = cameraFromTCamera(toTCamera(cam));
  EXPECT_EQ(back.describe(), cam.describe());
}
}  // namespace
}  // namespace st

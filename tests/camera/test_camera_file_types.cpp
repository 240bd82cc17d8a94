// Issue 39, "silently wrong": camera files were read without their types and ranges checked:
// `image_width: "wide"` became 2147483647 (and `catalog build` wrote a 393 MB database for
// it), `dt: s` truncated every value to an integer (k1 became 0), `k1: 1e6` was accepted, and
// a 100000 x 100000 camera passed `config`. Every field is now checked for type, range and
// what a lens can do, naming the file and the field.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <fstream>
#include <regex>
#include <string>

#include "common/conventions.hpp"
#include "common/errors.hpp"
#include "sensors/camera/camera_model.hpp"
#include "tests/support/test_paths.hpp"

namespace st {
namespace {

/// A real calibrated camera file (Swarm's head A: 752x290, rows binned) as text.
const char* kCamera = R"(%YAML:1.0
---
image_width: 752
image_height: 290
camera_matrix: !!opencv-matrix
   rows: 3
   cols: 3
   dt: d
   data: [ 2328.579, 0., 376.911, 0., 1206.489, 135.154, 0., 0., 1. ]
distortion_coefficients: !!opencv-matrix
   rows: 1
   cols: 5
   dt: d
   data: [ -0.166, 0., 0., 0., 0. ]
)";

/// Loads kCamera with `from` replaced by `to`; returns the error ("" when it loads).
std::string loadError(const std::string& from, const std::string& to) {
  const std::string text = std::regex_replace(kCamera, std::regex(from), to);
  const std::string path = test::makeTempDir("camera_types") + "/cam.yaml";
  std::ofstream(path) << text;
  try {
    CameraModel::loadYaml(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(CameraFileTypes, TheRealFileLoads) { EXPECT_EQ(loadError("x^", ""), ""); }

TEST(CameraFileTypes, ASizeThatIsNotANumberIsRefused) {
  EXPECT_THAT(loadError("image_width: 752", "image_width: \"wide\""),
              ::testing::HasSubstr("cam.yaml: key 'image_width' = 'wide': not a number"));
  EXPECT_THAT(loadError("image_height: 290", "image_height: 290.5"),
              ::testing::HasSubstr("key 'image_height' = 290.5"));
}

TEST(CameraFileTypes, AnIntegerMatrixTypeIsRefusedNotTruncated) {
  EXPECT_THAT(loadError("dt: d\n   data: \\[ -0.166", "dt: s\n   data: [ -0.166"),
              ::testing::HasSubstr("key 'distortion_coefficients': dt 's' is not a floating type"));
  EXPECT_THAT(loadError("-0.166", "k1"),
              ::testing::HasSubstr("key 'distortion_coefficients': 'k1' is not a number"));
}

TEST(CameraFileTypes, SizesFocalLengthsAndThePrincipalPointHaveRanges) {
  EXPECT_THAT(loadError("image_width: 752", "image_width: 100000"),
              ::testing::HasSubstr("image size must be 1 to 32768 px a side"));
  EXPECT_THAT(loadError("image_width: 752", "image_width: 0"), ::testing::HasSubstr("image size"));
  EXPECT_THAT(loadError("2328.579", "1e12"), ::testing::HasSubstr("focal lengths must be in"));
  // The principal point on the sensor: 376.9 px is inside 752, 3769 is not.
  EXPECT_THAT(loadError("376.911", "3769.11"),
              ::testing::HasSubstr("principal point (3769.110000, 135.154000) must be inside"));
  EXPECT_THAT(loadError("135.154", "-20"), ::testing::HasSubstr("principal point"));
}

TEST(CameraFileTypes, DistortionBeyondWhatALensCanDoIsRefused) {
  // k1 = 1e6 (a typo): every point off the centre moved many times its radius.
  EXPECT_THAT(loadError("-0.166", "1e6"), ::testing::HasSubstr("is not a lens"));
  // A strong negative k1 folds the corners back inward (the Jacobian changes sign).
  EXPECT_THAT(loadError("-0.166", "-40"), ::testing::HasSubstr("is not a lens"));
  // A real wide-angle barrel distortion stays.
  EXPECT_EQ(loadError("-0.166", "-0.4"), "");
}

TEST(CameraFileTypes, FromFovTakesTheSameRanges) {
  EXPECT_THROW(CameraModel::fromFov(100000, 100000, deg2rad(10)), InputError);
  EXPECT_THROW(CameraModel::fromFov(40000, 20000, deg2rad(10)), InputError);  // > 2^28 px
  EXPECT_NO_THROW(CameraModel::fromFov(16384, 16384, deg2rad(10)));
}

}  // namespace
}  // namespace st

/// @file camera_model.hpp
/// Pinhole camera with OpenCV's radial-tangential distortion (k1, k2, p1, p2, k3).
/// Frames and pixel convention: common/conventions.hpp (+z boresight, +x column, +y row,
/// pixel centres at integer coordinates).
///
/// Class invariant: fx, fy > 0, width, height > 0.
#pragma once
#include <array>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include <functional>

#include "startracker/attitude.hpp"

namespace st {

/// OpenCV distortion coefficients in OpenCV's order.
struct Distortion {
  double k1 = 0, k2 = 0, p1 = 0, p2 = 0, k3 = 0;
  bool isZero() const { return k1 == 0 && k2 == 0 && p1 == 0 && p2 == 0 && k3 == 0; }
};

class CameraModel {
 public:
  CameraModel() = default;
  /// Throws InputError naming the bad value if the invariant does not hold.
  CameraModel(int width, int height, double fx, double fy, double cx, double cy,
              Distortion dist = {}, const std::string& source = "camera model");

  /// The common case: square pixels, principal point at the image centre
  /// ((w-1)/2, (h-1)/2), no distortion, horizontal field of view `hfov` [rad].
  /// `pixel_aspect` (a pixel's height over its width on the sky; 2 for rows binned 2x) makes
  /// fy = fx / pixel_aspect.
  static CameraModel fromFov(int width, int height, double hfov, double pixel_aspect = 1);

  /// OpenCV cv::FileStorage YAML/XML with the keys OpenCV's calibration writes:
  /// `camera_matrix` (3x3), `distortion_coefficients` (4, 5 or more; extra terms must be 0),
  /// `image_width`, `image_height`. Throws InputError naming the file and key.
  static CameraModel loadYaml(const std::string& path);
  void saveYaml(const std::string& path) const;

  /// A camera file by its name: an MRPT .ini (`section` of it) through the reader the MRPT
  /// adapters register (setIniCameraReader), anything else loadYaml.
  static CameraModel loadFile(const std::string& path, const std::string& section = "CAMERA");

  int width() const { return width_; }
  int height() const { return height_; }
  double fx() const { return fx_; }
  double fy() const { return fy_; }
  double cx() const { return cx_; }
  double cy() const { return cy_; }
  const Distortion& distortion() const { return dist_; }

  /// Unit vector in the camera frame of the ray through pixel `px` (distortion removed by
  /// Newton iteration to ~1e-14 in normalised coordinates).
  Vec3 pixelToVector(const Vec2& px) const;
  /// Pixel of the camera-frame direction `v_cam`; nullopt when v_cam points behind the
  /// camera (z <= 0). Does not check the image bounds: see isPixelInImage.
  std::optional<Vec2> vectorToPixel(const Vec3& v_cam) const;
  /// 2x2 Jacobian d(pixel)/d(normalised image coordinates x/z, y/z) at `v_cam`, for turning
  /// pixel covariances into angular ones.
  Mat2 pixelJacobian(const Vec3& v_cam) const;

  /// True when the pixel lies inside the image shrunk by `margin_px` on each side.
  bool isPixelInImage(const Vec2& px, double margin_px = 0) const;
  /// True when `v_cam` projects inside the image (shrunk by margin_px).
  bool isVectorInImage(const Vec3& v_cam, double margin_px = 0) const;

  /// The image corners (-0.5,-0.5), (w-0.5,-0.5), (w-0.5,h-0.5), (-0.5,h-0.5) as unit vectors.
  std::array<Vec3, 4> cornerVectors() const;
  /// Full horizontal and vertical field of view through the principal point [rad].
  double horizontalFov() const;
  double verticalFov() const;
  /// Angle from the boresight to the farthest corner [rad]: radius of the cone that holds
  /// the whole image.
  double halfDiagonalFov() const;
  /// Mean angular size of a pixel near the centre [rad/px].
  double pixelScale() const { return 2.0 / (fx_ + fy_); }
  /// A pixel's height over its width on the sky, fx / fy (1: square; 2: rows binned 2x).
  double pixelAspect() const { return fx_ / fy_; }

  std::string describe() const;

 private:
  Vec2 distortNormalised(const Vec2& xy) const;
  Vec2 undistortNormalised(const Vec2& xy_d) const;
  void validate(const std::string& source) const;

  int width_ = 0, height_ = 0;
  double fx_ = 0, fy_ = 0, cx_ = 0, cy_ = 0;
  Distortion dist_;
};

/// The image sizes taken: a side of at most 32768 px and at most 2^28 pixels (268 MP, 512 MB
/// at 16 bits), beyond any star camera, so that no camera file makes a command allocate
/// without bound.
constexpr int kMaxImageSide = 32768;
constexpr long long kMaxImagePixels = 1LL << 28;
/// Focal lengths taken [px]: from a 1 px lens (a near-hemispheric view) to a 0.002"/px one.
constexpr double kMinFocalPx = 1, kMaxFocalPx = 1e8;
/// The largest radial displacement the distortion model may make anywhere in the image, as a
/// fraction of the radius: a lens a star camera uses stays well inside; beyond it OpenCV's
/// polynomial is not a lens (and a number like k1 = 1e6 is a typo).
constexpr double kMaxDistortionFraction = 0.5;
/// The pixel aspects taken (binning up to 8x in one direction).
constexpr double kMinPixelAspect = 0.125, kMaxPixelAspect = 8;
/// True for a pixel aspect (CameraModel::pixelAspect) within 0.1 % of 1: a camera calibrated
/// with square pixels keeps them in every fit.
inline bool hasSquarePixels(double pixel_aspect) { return std::abs(pixel_aspect - 1) < 1e-3; }

/// Throws InputError naming the file when `path` is missing or a directory.
void requireCameraFile(const std::string& path);
/// OpenCV's coefficient vector (4, 5 or more, extra terms 0) as a Distortion; InputError
/// naming `where` otherwise.
Distortion distortionFromVector(const std::vector<double>& d, const std::string& where);

/// Reads `section` of an MRPT .ini camera file. The core camera stage does not link MRPT: the
/// MRPT adapters install their reader (sensors/mrpt/camera_ini.hpp) in the programs that
/// link them.
using CameraFileReader = std::function<CameraModel(const std::string& path, const std::string& section)>;
void setIniCameraReader(CameraFileReader reader);
/// True for a camera file name ending in ".ini".
bool isIniCameraPath(const std::string& path);

}  // namespace st

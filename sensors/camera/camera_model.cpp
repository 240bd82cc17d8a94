#include "common/output_file.hpp"
#include "sensors/camera/camera_model.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <opencv2/core.hpp>
#include <sstream>
#include <vector>

#include "common/conventions.hpp"
#include "common/errors.hpp"

namespace st {

namespace {
Mat2 distortionJacobian(const Distortion& d, const Vec2& xy);
}  // namespace

CameraModel::CameraModel(int width, int height, double fx, double fy, double cx, double cy,
                         Distortion dist, const std::string& source)
    : width_(width), height_(height), fx_(fx), fy_(fy), cx_(cx), cy_(cy), dist_(dist) {
  validate(source);
}

void CameraModel::validate(const std::string& source) const {
  auto bad = [&](const std::string& what) { throw InputError(source + ": " + what); };
  if (width_ <= 0 || height_ <= 0 || width_ > kMaxImageSide || height_ > kMaxImageSide ||
      static_cast<long long>(width_) * height_ > kMaxImagePixels)
    bad("image size must be 1 to " + std::to_string(kMaxImageSide) + " px a side and at most " +
        std::to_string(kMaxImagePixels) + " pixels, got " + std::to_string(width_) + "x" +
        std::to_string(height_));
  if (!(fx_ >= kMinFocalPx && fx_ <= kMaxFocalPx) || !(fy_ >= kMinFocalPx && fy_ <= kMaxFocalPx))
    bad("focal lengths must be in [1, 1e8] px, got fx=" + std::to_string(fx_) +
        " fy=" + std::to_string(fy_));
  if (!(fx_ / fy_ >= kMinPixelAspect && fx_ / fy_ <= kMaxPixelAspect))
    bad("fx / fy (the pixel aspect) must be in [" + std::to_string(kMinPixelAspect) + ", " +
        std::to_string(kMaxPixelAspect) + "], got " + std::to_string(fx_ / fy_));
  // The principal point is where the optical axis meets the sensor: on it.
  if (!(cx_ >= -0.5 && cx_ <= width_ - 0.5) || !(cy_ >= -0.5 && cy_ <= height_ - 0.5))
    bad("principal point (" + std::to_string(cx_) + ", " + std::to_string(cy_) +
        ") must be inside the " + std::to_string(width_) + "x" + std::to_string(height_) +
        " image");
  for (double k : {dist_.k1, dist_.k2, dist_.p1, dist_.p2, dist_.k3})
    if (!std::isfinite(k)) bad("distortion coefficients must be finite");
  // What a lens can do: over the whole image the model moves no point by more than
  // kMaxDistortionFraction of its radius and never folds the image onto itself (its Jacobian
  // stays positive), on a 17 x 17 grid to the corners.
  constexpr int kGrid = 16;
  const bool pinhole = dist_.k1 == 0 && dist_.k2 == 0 && dist_.p1 == 0 && dist_.p2 == 0 && dist_.k3 == 0;
  for (int i = 0; i <= kGrid && !pinhole; ++i) {
    for (int j = 0; j <= kGrid; ++j) {
      const Vec2 xy((width_ * i / double(kGrid) - 0.5 - cx_) / fx_,
                    (height_ * j / double(kGrid) - 0.5 - cy_) / fy_);
      const double r = xy.norm();
      if (r == 0) continue;
      const Vec2 d = distortNormalised(xy);
      const double moved = (d - xy).norm() / r;
      const double det = distortionJacobian(dist_, xy).determinant();
      if (!(moved <= kMaxDistortionFraction) || !(det > 0)) {
        std::ostringstream what;
        what << "distortion k1=" << dist_.k1 << " k2=" << dist_.k2 << " p1=" << dist_.p1
             << " p2=" << dist_.p2 << " k3=" << dist_.k3 << " is not a lens: at pixel ("
             << width_ * i / double(kGrid) - 0.5 << ", " << height_ * j / double(kGrid) - 0.5
             << ") it "
             << (det > 0 ? "moves a point by " + std::to_string(int(std::round(100 * moved))) +
                               " % of its distance from the centre (at most " +
                               std::to_string(int(100 * kMaxDistortionFraction)) + " %)"
                         : std::string("folds the image onto itself"));
        bad(what.str());
      }
    }
  }
}

CameraModel CameraModel::fromFov(int width, int height, double hfov, double pixel_aspect) {
  if (!(hfov > 0) || !(hfov < kPi))
    throw InputError("field of view must be in (0, 180) deg, got " +
                     std::to_string(rad2deg(hfov)) + " deg");
  if (!(pixel_aspect >= kMinPixelAspect && pixel_aspect <= kMaxPixelAspect))
    throw InputError("pixel aspect must be in [" + std::to_string(kMinPixelAspect) + ", " +
                     std::to_string(kMaxPixelAspect) + "], got " + std::to_string(pixel_aspect));
  const double f = 0.5 * width / std::tan(0.5 * hfov);
  return CameraModel(width, height, f, f / pixel_aspect, 0.5 * (width - 1), 0.5 * (height - 1));
}

// OpenCV's distortion model (cv::projectPoints documentation).
Vec2 CameraModel::distortNormalised(const Vec2& xy) const {
  const double x = xy.x(), y = xy.y();
  const double r2 = x * x + y * y;
  const double radial = 1 + r2 * (dist_.k1 + r2 * (dist_.k2 + r2 * dist_.k3));
  return {x * radial + 2 * dist_.p1 * x * y + dist_.p2 * (r2 + 2 * x * x),
          y * radial + dist_.p1 * (r2 + 2 * y * y) + 2 * dist_.p2 * x * y};
}

namespace {
Mat2 distortionJacobian(const Distortion& d, const Vec2& xy) {
  const double x = xy.x(), y = xy.y();
  const double r2 = x * x + y * y;
  const double radial = 1 + r2 * (d.k1 + r2 * (d.k2 + r2 * d.k3));
  const double dradial = d.k1 + 2 * d.k2 * r2 + 3 * d.k3 * r2 * r2;  // d(radial)/d(r2)
  Mat2 J;
  J(0, 0) = radial + 2 * x * x * dradial + 2 * d.p1 * y + 6 * d.p2 * x;
  J(0, 1) = 2 * x * y * dradial + 2 * d.p1 * x + 2 * d.p2 * y;
  J(1, 0) = 2 * x * y * dradial + 2 * d.p1 * x + 2 * d.p2 * y;
  J(1, 1) = radial + 2 * y * y * dradial + 6 * d.p1 * y + 2 * d.p2 * x;
  return J;
}
}  // namespace

Vec2 CameraModel::undistortNormalised(const Vec2& xy_d) const {
  if (dist_.isZero()) return xy_d;
  // Newton's method on distort(xy) = xy_d, starting from the distorted point; the map is
  // close to the identity for real lenses, so this converges in a few steps.
  Vec2 xy = xy_d;
  for (int it = 0; it < 50; ++it) {
    const Vec2 r = distortNormalised(xy) - xy_d;
    if (r.norm() < 1e-15) break;
    xy -= distortionJacobian(dist_, xy).lu().solve(r);
  }
  return xy;
}

Vec3 CameraModel::pixelToVector(const Vec2& px) const {
  const Vec2 xy_d((px.x() - cx_) / fx_, (px.y() - cy_) / fy_);
  const Vec2 xy = undistortNormalised(xy_d);
  return Vec3(xy.x(), xy.y(), 1.0).normalized();
}

std::optional<Vec2> CameraModel::vectorToPixel(const Vec3& v_cam) const {
  if (!(v_cam.z() > 0)) return std::nullopt;
  const Vec2 xy_d = distortNormalised(Vec2(v_cam.x() / v_cam.z(), v_cam.y() / v_cam.z()));
  return Vec2(fx_ * xy_d.x() + cx_, fy_ * xy_d.y() + cy_);
}

Mat2 CameraModel::pixelJacobian(const Vec3& v_cam) const {
  const Vec2 xy(v_cam.x() / v_cam.z(), v_cam.y() / v_cam.z());
  return Eigen::Vector2d(fx_, fy_).asDiagonal() * distortionJacobian(dist_, xy);
}

bool CameraModel::isPixelInImage(const Vec2& px, double margin_px) const {
  return px.x() >= -0.5 + margin_px && px.x() <= width_ - 0.5 - margin_px &&
         px.y() >= -0.5 + margin_px && px.y() <= height_ - 0.5 - margin_px;
}

bool CameraModel::isVectorInImage(const Vec3& v_cam, double margin_px) const {
  const auto px = vectorToPixel(v_cam);
  return px && isPixelInImage(*px, margin_px);
}

std::array<Vec3, 4> CameraModel::cornerVectors() const {
  const double l = -0.5, r = width_ - 0.5, t = -0.5, b = height_ - 0.5;
  return {pixelToVector({l, t}), pixelToVector({r, t}), pixelToVector({r, b}),
          pixelToVector({l, b})};
}

double CameraModel::horizontalFov() const {
  const Vec3 a = pixelToVector({-0.5, cy_}), b = pixelToVector({width_ - 0.5, cy_});
  return std::acos(std::clamp(a.dot(b), -1.0, 1.0));
}

double CameraModel::verticalFov() const {
  const Vec3 a = pixelToVector({cx_, -0.5}), b = pixelToVector({cx_, height_ - 0.5});
  return std::acos(std::clamp(a.dot(b), -1.0, 1.0));
}

double CameraModel::halfDiagonalFov() const {
  double best = 0;
  for (const Vec3& c : cornerVectors()) best = std::max(best, std::acos(std::clamp(c.z(), -1.0, 1.0)));
  return best;
}

std::string CameraModel::describe() const {
  std::ostringstream os;
  os.precision(10);
  os << width_ << "x" << height_ << " px, fx=" << fx_ << " fy=" << fy_ << " cx=" << cx_
     << " cy=" << cy_ << ", dist=[" << dist_.k1 << " " << dist_.k2 << " " << dist_.p1 << " "
     << dist_.p2 << " " << dist_.k3 << "]";
  os.precision(4);
  os << ", FOV " << rad2deg(horizontalFov()) << " x " << rad2deg(verticalFov()) << " deg";
  return os.str();
}

// ---- files --------------------------------------------------------------------------

void requireCameraFile(const std::string& path) {
  if (!std::filesystem::exists(path)) throw InputError(path + ": camera file does not exist");
  if (std::filesystem::is_directory(path))
    throw InputError(path + ": camera file is a directory");
}

Distortion distortionFromVector(const std::vector<double>& d, const std::string& where) {
  if (d.size() < 4)
    throw InputError(where + ": distortion coefficients need at least 4 values (k1 k2 p1 p2 [k3]), got " +
                     std::to_string(d.size()));
  for (std::size_t i = 5; i < d.size(); ++i)
    if (d[i] != 0)
      throw InputError(where + ": only the 5-term model (k1 k2 p1 p2 k3) is supported; term " +
                       std::to_string(i) + " is non-zero");
  Distortion dist{d[0], d[1], d[2], d[3], d.size() > 4 ? d[4] : 0.0};
  return dist;
}

namespace {
CameraFileReader& iniReaderHook() {
  static CameraFileReader reader;
  return reader;
}
}  // namespace

void setIniCameraReader(CameraFileReader reader) { iniReaderHook() = std::move(reader); }

bool isIniCameraPath(const std::string& path) {
  return path.size() > 4 && path.compare(path.size() - 4, 4, ".ini") == 0;
}

CameraModel CameraModel::loadFile(const std::string& path, const std::string& section) {
  if (!isIniCameraPath(path)) return loadYaml(path);
  if (!iniReaderHook())
    throw InputError(path + ": MRPT .ini camera files are read by the MRPT adapters "
                     "(sensors/mrpt/camera_ini.hpp), which this program does not link");
  return iniReaderHook()(path, section);
}

/// A '!' that is not part of a "!!" tag, outside comments and quotes; npos when none. OpenCV
/// writes only "!!opencv-matrix"-style tags.
std::size_t singleBangTag(const std::string& text) {
  bool quoted = false, comment = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (c == '\n') {
      quoted = comment = false;
    } else if (comment) {
    } else if (c == '"') {
      quoted = !quoted;
    } else if (c == '#' && !quoted) {
      comment = true;
    } else if (c == '!' && !quoted) {
      if (i + 1 < text.size() && text[i + 1] == '!') {
        ++i;
      } else {
        return i;
      }
    }
  }
  return std::string::npos;
}

/// OpenCV 4.6's YAML reader loops forever on some malformed text (found by fuzzing, checked
/// outside the fuzzer; tests/fuzz/regressions/camera/): a NUL byte, or a single-'!' tag such as
/// "!pe-" on a line after an indented key. Both are refused before OpenCV sees the file; no
/// camera file OpenCV writes has either. Its gzip form (*.gz) is OpenCV's to check. Camera
/// files are a few KB; 1 MB is no camera file.
void requireTextFile(const std::string& path) {
  if (path.size() > 3 && path.compare(path.size() - 3, 3, ".gz") == 0) return;
  constexpr std::uintmax_t kMaxBytes = 1 << 20;
  std::error_code ec;
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  if (!ec && size > kMaxBytes)
    throw InputError(path + ": " + std::to_string(size) + " bytes is too large for a camera file (at most 1 MB)");
  std::ifstream in(path, std::ios::binary);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (const auto at = text.find('\0'); at != std::string::npos)
    throw InputError(path + ": a NUL byte at offset " + std::to_string(at) +
                     ": not a text (YAML/XML) camera file");
  const auto first = text.find_first_not_of(" \t\r\n");
  const bool xml = first != std::string::npos && text[first] == '<';
  if (!xml) {
    if (const auto at = singleBangTag(text); at != std::string::npos)
      throw InputError(path + ": a YAML tag with a single '!' at offset " + std::to_string(at) +
                       " (OpenCV camera files use '!!' tags such as !!opencv-matrix)");
  }
}

namespace {

/// A whole number written as a number (OpenCV reads the text "wide" as INT_MAX).
int integerNode(const cv::FileNode& n, const std::string& where) {
  if (!n.isInt() && !n.isReal())
    throw InputError(where + " = '" + (n.isString() ? n.string() : std::string("(not a value)")) +
                     "': not a number");
  const double v = n.real();
  if (!std::isfinite(v) || v != std::floor(v) || std::abs(v) > 1e9)
    throw InputError(where + " = " + std::to_string(v) + ": not a whole number of pixels");
  return static_cast<int>(v);
}

/// A matrix node of a camera file: an OpenCV matrix of a floating type ('d' or 'f': an integer
/// type such as 's' truncates every value, k1 = -0.08 becoming 0) whose data are numbers, or
/// a plain sequence of numbers.
void requireRealMatrix(const cv::FileNode& n, const std::string& where) {
  cv::FileNode data = n;
  if (n.isMap()) {
    const cv::FileNode dt = n["dt"];
    const std::string type = dt.isString() ? dt.string() : "";
    if (type != "d" && type != "f")
      throw InputError(where + ": dt '" + type +
                       "' is not a floating type (an integer type truncates the values; "
                       "camera files use 'd')");
    data = n["data"];
  }
  if (!data.isSeq()) throw InputError(where + ": not a matrix or a sequence of numbers");
  for (const cv::FileNode& v : data)
    if (!v.isInt() && !v.isReal())
      throw InputError(where + ": '" + (v.isString() ? v.string() : std::string("?")) +
                       "' is not a number");
}

}  // namespace

CameraModel CameraModel::loadYaml(const std::string& path) {
  requireCameraFile(path);
  requireTextFile(path);
  cv::FileStorage fs;
  try {
    fs.open(path, cv::FileStorage::READ);
  } catch (const cv::Exception& e) {
    throw InputError(path + ": not a readable OpenCV YAML/XML camera file (" + e.err + ")");
  } catch (const std::exception& e) {  // found by fuzzing: std::length_error from the parser
    throw InputError(path + ": not a readable OpenCV YAML/XML camera file (" + e.what() + ")");
  }
  if (!fs.isOpened()) throw InputError(path + ": cannot open camera file");
  auto need = [&](const char* key) {
    cv::FileNode n = fs[key];
    if (n.empty()) throw InputError(path + ": missing key '" + key + "'");
    return n;
  };
  cv::Mat K, D;
  int w = 0, h = 0;
  try {
    // A matrix declares its size: check it before OpenCV allocates that much (found by fuzzing:
    // a declared 10^9 x 10^9 matrix took the reader minutes and gigabytes).
    auto small = [&](const char* key) {
      cv::FileNode n = need(key);
      if (n.isMap() && (int64_t(int(n["rows"])) * int64_t(int(n["cols"])) > 16 ||
                        int(n["rows"]) < 0 || int(n["cols"]) < 0))
        throw InputError(path + ": key '" + key + "' declares a " + std::to_string(int(n["rows"])) +
                         "x" + std::to_string(int(n["cols"])) + " matrix (at most 16 values)");
      requireRealMatrix(n, path + ": key '" + key + "'");
      return n;
    };
    small("camera_matrix") >> K;
    small("distortion_coefficients") >> D;
    w = integerNode(need("image_width"), path + ": key 'image_width'");
    h = integerNode(need("image_height"), path + ": key 'image_height'");
  } catch (const cv::Exception& e) {
    throw InputError(path + ": malformed camera file (" + e.err + ")");
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    throw InputError(path + ": malformed camera file (" + e.what() + ")");
  }
  if (K.rows != 3 || K.cols != 3)
    throw InputError(path + ": key 'camera_matrix' must be a 3x3 matrix");
  K.convertTo(K, CV_64F);
  D.convertTo(D, CV_64F);
  std::vector<double> d(D.begin<double>(), D.end<double>());
  CameraModel cam;
  cam.width_ = w;
  cam.height_ = h;
  cam.fx_ = K.at<double>(0, 0);
  cam.fy_ = K.at<double>(1, 1);
  cam.cx_ = K.at<double>(0, 2);
  cam.cy_ = K.at<double>(1, 2);
  cam.dist_ = distortionFromVector(d, path + ": key 'distortion_coefficients'");
  cam.validate(path);
  return cam;
}

void CameraModel::saveYaml(const std::string& path) const {
  PendingOutput out(path);  // the extension stays: FileStorage picks YAML or XML by it
  {
    cv::FileStorage fs(out.tempPath(), cv::FileStorage::WRITE);
    if (!fs.isOpened()) throw InputError(path + ": cannot write camera file");
    cv::Mat K = (cv::Mat_<double>(3, 3) << fx_, 0, cx_, 0, fy_, cy_, 0, 0, 1);
    cv::Mat D = (cv::Mat_<double>(1, 5) << dist_.k1, dist_.k2, dist_.p1, dist_.p2, dist_.k3);
    fs << "image_width" << width_ << "image_height" << height_ << "camera_matrix" << K
       << "distortion_coefficients" << D;
  }
  out.commit();
}

namespace {
}  // namespace

}  // namespace st

#include "sensors/detect/radiation_hits.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace st::detect_detail {
namespace {

// A profile no narrower than a flat one (neighbours as high as the peak).
constexpr double kFlat = 1e9;

template <typename T>
double at(const cv::Mat& m, int x, int y) {
  return static_cast<double>(m.ptr<T>(y)[x]);
}

// v: peak, left, right, up, down, up-left, down-right, up-right, down-left (above b).
template <typename T>
void neighbours(const cv::Mat& g, int x, int y, double b, double v[9]) {
  constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  const auto get = [&](int dx, int dy) {
    const int xx = x + dx, yy = y + dy;
    return xx >= 0 && yy >= 0 && xx < g.cols && yy < g.rows ? at<T>(g, xx, yy) - b : nan;
  };
  v[0] = get(0, 0), v[1] = get(-1, 0), v[2] = get(1, 0), v[3] = get(0, -1), v[4] = get(0, 1);
  v[5] = get(-1, -1), v[6] = get(1, 1), v[7] = get(1, -1), v[8] = get(-1, 1);
}

void values(const cv::Mat& g, int x, int y, double b, double v[9]) {
  if (g.depth() == CV_8U)
    neighbours<uint8_t>(g, x, y, b, v);
  else
    neighbours<uint16_t>(g, x, y, b, v);
}

// s of three values: P (middle) and its neighbours L, R above the background.
double threePointWidth(double l, double p, double r) {
  if (!(l > 0 && r > 0 && p > 0)) return 0;
  const double curv = 2 * std::log(p) - std::log(l) - std::log(r);
  return curv > 0 ? 1 / std::sqrt(curv) : kFlat;
}

// A star's neighbour ratio along an axis of width s: r (a sampled Gaussian at phase 0).
double ratio(double s) { return std::exp(-1 / (2 * s * s)); }

}  // namespace

PeakProfile peakProfile(const cv::Mat& grey, int px, int py, double b) {
  double v[9];
  values(grey, px, py, b, v);
  return {v[0], v[1] + v[2], v[3] + v[4], v[5] + v[6], v[7] + v[8]};
}

AxisWidth profileWidth(const cv::Mat& grey, int px, int py, double b) {
  double v[9];
  values(grey, px, py, b, v);
  return {threePointWidth(v[1], v[0], v[2]), threePointWidth(v[3], v[0], v[4])};
}

AxisWidth frameWidth(const std::vector<AxisWidth>& blobs) {
  const std::size_t n = blobs.size();
  if (static_cast<int>(n) < kMinPsfBlobs) return {};
  const double tol = std::log(1 + kClusterTolerance);
  const auto near = [tol](const AxisWidth& a, const AxisWidth& b) {
    return std::abs(std::log(a.x / b.x)) < tol && std::abs(std::log(a.y / b.y)) < tol;
  };
  // The largest cluster (a tie to the wider): the stars share one PSF, hits scatter with
  // their track's length and angle.
  std::size_t best = 0;
  int best_count = -1;
  for (std::size_t i = 0; i < n; ++i) {
    int count = 0;
    for (std::size_t j = 0; j < n; ++j) count += near(blobs[i], blobs[j]);
    if (count > best_count ||
        (count == best_count && blobs[i].x * blobs[i].y > blobs[best].x * blobs[best].y))
      best = i, best_count = count;
  }
  if (best_count < kMinPsfBlobs / 2 + 1) return {};
  std::vector<double> xs, ys;
  for (const AxisWidth& w : blobs)
    if (near(blobs[best], w)) xs.push_back(w.x), ys.push_back(w.y);
  const auto median = [](std::vector<double>& v) {
    const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
    std::nth_element(v.begin(), mid, v.end());
    return *mid;
  };
  return {median(xs), median(ys)};
}

bool sharperThanPsf(const PeakProfile& p, double sigma, double psf_x, double psf_y) {
  const double give = kNoiseSigmas * std::sqrt(2.0) * sigma;  // the sum of two pixels' noise
  // A star's least sum of two opposite neighbours, over its peak: 2 r along an axis, 2 r_x r_y
  // along a diagonal (separable PSF).
  const auto bare = [&](double sum, double least) {
    // NaN (a neighbour outside the image) compares false: no verdict along that direction.
    return sum + give < kNeighbourFraction * least * p.peak;
  };
  if (!(psf_x > 0 && psf_y > 0)) return false;
  const double rx = ratio(psf_x), ry = ratio(psf_y);
  return bare(p.along_x, 2 * rx) || bare(p.along_y, 2 * ry) || bare(p.diagonal, 2 * rx * ry) ||
         bare(p.antidiagonal, 2 * rx * ry);
}

}  // namespace st::detect_detail

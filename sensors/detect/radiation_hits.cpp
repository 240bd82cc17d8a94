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

template <typename T>
void neighbours(const cv::Mat& g, int x, int y, double b, double v[5]) {
  constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  v[0] = at<T>(g, x, y) - b;
  v[1] = x > 0 ? at<T>(g, x - 1, y) - b : nan;
  v[2] = x + 1 < g.cols ? at<T>(g, x + 1, y) - b : nan;
  v[3] = y > 0 ? at<T>(g, x, y - 1) - b : nan;
  v[4] = y + 1 < g.rows ? at<T>(g, x, y + 1) - b : nan;
}

void values(const cv::Mat& g, int x, int y, double b, double v[5]) {
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

// A star's least neighbour sum along an axis of width s, over its peak: 2 r.
double leastNeighbours(double s) { return 2 * std::exp(-1 / (2 * s * s)); }

}  // namespace

PeakProfile peakProfile(const cv::Mat& grey, int px, int py, double b) {
  double v[5];
  values(grey, px, py, b, v);
  return {v[0], v[1] + v[2], v[3] + v[4]};
}

AxisWidth profileWidth(const cv::Mat& grey, int px, int py, double b) {
  double v[5];
  values(grey, px, py, b, v);
  return {threePointWidth(v[1], v[0], v[2]), threePointWidth(v[3], v[0], v[4])};
}

double medianWidth(std::vector<double>& v) {
  v.erase(std::remove(v.begin(), v.end(), 0.0), v.end());
  if (static_cast<int>(v.size()) < kMinPsfBlobs) return 0;
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

bool sharperThanPsf(const PeakProfile& p, double sigma, double psf_x, double psf_y) {
  const double give = kNoiseSigmas * std::sqrt(2.0) * sigma;  // the sum of two pixels' noise
  const auto bare = [&](double sum, double s) {
    // NaN (a neighbour outside the image) compares false: no verdict along that axis.
    return s > 0 && sum + give < kNeighbourFraction * leastNeighbours(s) * p.peak;
  };
  return bare(p.along_x, psf_x) || bare(p.along_y, psf_y);
}

}  // namespace st::detect_detail

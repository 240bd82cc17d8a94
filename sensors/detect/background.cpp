#include "sensors/detect/background.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace st {
namespace {

// Regular subsample of roughly `n` pixels of the ROI (a strided grid, deterministic).
template <typename T>
void sample(const cv::Mat& roi, int n, std::vector<float>& out) {
  out.clear();
  const double area = static_cast<double>(roi.rows) * roi.cols;
  const int stride = std::max(1, static_cast<int>(std::sqrt(area / std::max(n, 1))));
  // Offset odd rows by half a stride so columns are not always the same.
  for (int r = stride / 2; r < roi.rows; r += stride) {
    const T* row = roi.ptr<T>(r);
    for (int c = ((r / stride) & 1) ? stride / 2 : 0; c < roi.cols; c += stride)
      out.push_back(static_cast<float>(row[c]));
  }
  if (out.empty()) out.push_back(static_cast<float>(roi.at<T>(0, 0)));
}

void sampleAny(const cv::Mat& roi, int n, std::vector<float>& out) {
  if (roi.depth() == CV_8U)
    sample<uint8_t>(roi, n, out);
  else
    sample<uint16_t>(roi, n, out);
}

double bilinear(const BackgroundModel& m, const std::vector<float>& t, double x, double y) {
  // Tile centres at (k + 0.5) * tile - 0.5; clamp outside the outer centres.
  const double fx = std::clamp((x + 0.5) / m.tile - 0.5, 0.0, m.tiles_x - 1.0);
  const double fy = std::clamp((y + 0.5) / m.tile - 0.5, 0.0, m.tiles_y - 1.0);
  const int x0 = std::min(static_cast<int>(fx), m.tiles_x - 1);
  const int y0 = std::min(static_cast<int>(fy), m.tiles_y - 1);
  const int x1 = std::min(x0 + 1, m.tiles_x - 1), y1 = std::min(y0 + 1, m.tiles_y - 1);
  const double ax = fx - x0, ay = fy - y0;
  auto at = [&](int i, int j) { return static_cast<double>(t[static_cast<std::size_t>(j * m.tiles_x + i)]); };
  return (1 - ay) * ((1 - ax) * at(x0, y0) + ax * at(x1, y0)) +
         ay * ((1 - ax) * at(x0, y1) + ax * at(x1, y1));
}

}  // namespace

namespace {
// Quantisation step of the samples: the largest power of two dividing all of them (an ADC of
// b bits whose values are shifted into a 16-bit word counts in steps of 2^(16-b): the tetra3
// frames step by 16), 1 for too few samples to tell, 0 if some sample is not a whole number.
int32_t quantisationStep(const std::vector<float>& v) {
  int32_t bits = 0;
  bool whole = true;
  for (float x : v) {
    const bool in_range = std::abs(x) < 1e9f;
    const int32_t i = in_range ? static_cast<int32_t>(x) : 0;
    whole &= in_range & (static_cast<float>(i) == x);
    bits |= i;
  }
  if (!whole) return 0;
  // All of n random noise samples share a factor of 2 with probability 2^-n: trust it only
  // for a long list.
  if (bits == 0 || v.size() < 24) return 1;
  return bits & -bits;
}

// Quantiles of quantised samples read as grouped data: each value k stands for the interval
// [k - step/2, k + step/2) (what the ADC rounded), and the quantile is interpolated inside its
// interval. The plain order statistic of quantised data is itself a level: a median off by up
// to half a step and a MAD of 0 or 1 step when sigma ~ 1 step (8-bit cameras), i.e. a
// background bias and a noise estimate off by up to 40 %.
// For the order statistic m = x_(k), k = floor(p n): with `below` samples < m and `equal`
// samples == m, the quantile is m - step/2 + step (p n - below) / equal (not quantised: m).
double interpolateGroup(double m, int32_t step, double target, std::size_t below,
                        std::size_t equal) {
  if (step == 0) return m;
  return m + step * (-0.5 + (target - static_cast<double>(below)) / static_cast<double>(equal));
}

// The three quantiles p[0] <= p[1] <= p[2] of the samples (reordered in place). This runs for
// every tracking window's border ring: no comparison sort or selection (on noise, about every
// other comparison mispredicts) when a histogram will do: quantised values, counted per level
// from the lowest, those beyond the histogram (a star's pixels on the ring) in an overflow
// count that is fine as long as no quantile falls into it. Otherwise three selections on
// shrinking ranges and a count of the ties of each order statistic.
void groupedQuantiles(std::vector<float>& v, const double (&p)[3], double (&q)[3]) {
  const std::size_t n = v.size();
  std::size_t k[3];
  double target[3];
  for (int i = 0; i < 3; ++i) {
    target[i] = p[i] * static_cast<double>(n);
    k[i] = std::min(n - 1, static_cast<std::size_t>(target[i]));
  }
  const int32_t step = quantisationStep(v);
  if (step > 0) {
    const float lo = *std::min_element(v.begin(), v.end());
    const std::size_t bins = std::clamp<std::size_t>(2 * n, 256, 4096);
    const float inv_step = 1.0f / static_cast<float>(step);  // exact: a power of two
    thread_local std::vector<uint32_t> count;
    count.assign(bins + 1, 0);  // the last: overflow
    for (float x : v)
      ++count[std::min(static_cast<std::size_t>((x - lo) * inv_step), bins)];
    std::size_t bin = 0, below = 0;
    int i = 0;
    for (; i < 3; ++i) {
      while (bin < bins && below + count[bin] <= k[i]) below += count[bin++];
      if (bin == bins) break;  // in the overflow: select instead
      q[i] = interpolateGroup(lo + static_cast<double>(bin) * step, step, target[i], below,
                              count[bin]);
    }
    if (i == 3) return;
  }
  const auto at = [&](std::size_t i) { return v.begin() + static_cast<std::ptrdiff_t>(i); };
  std::nth_element(v.begin(), at(k[1]), v.end());
  if (k[0] < k[1]) std::nth_element(v.begin(), at(k[0]), at(k[1]));
  if (k[2] > k[1]) std::nth_element(at(k[1] + 1), at(k[2]), v.end());
  for (int i = 0; i < 3; ++i) {
    const float m = v[k[i]];
    std::size_t below = 0, equal = 0;
    for (float x : v) {
      below += x < m;
      equal += x == m;
    }
    q[i] = interpolateGroup(m, step, target[i], below, equal);
  }
}
}  // namespace

void robustLevelSigma(std::vector<float>& v, double& level, double& sigma) {
  // Median and interquartile range of the grouped data; IQR = 1.349 sigma for a Gaussian.
  // For Gaussian noise of sigma s rounded to integers the grouped quantiles are those of the
  // noise spread over the rounding interval, variance s^2 + 1/12: exactly the per-pixel
  // variance (noise + quantisation, seed 004 eq. 3.12) that the centroiders need.
  double q[3];
  groupedQuantiles(v, {0.25, 0.5, 0.75}, q);
  level = q[1];
  sigma = (q[2] - q[0]) / 1.349;
}

double BackgroundModel::levelAt(double x, double y) const {
  return tile > 0 ? bilinear(*this, tile_level, x, y) : level;
}
double BackgroundModel::sigmaAt(double x, double y) const {
  return tile > 0 ? bilinear(*this, tile_sigma, x, y) : sigma;
}

BackgroundModel estimateBackground(const cv::Mat& image, int tile, int samples,
                                   double sigma_floor) {
  BackgroundModel m;
  estimateBackground(image, tile, samples, sigma_floor, m);
  return m;
}

// Median of `v` through `tmp` (reused, so no allocation per frame).
static float medianOf(const std::vector<float>& v, std::vector<float>& tmp) {
  tmp.assign(v.begin(), v.end());
  const auto mid = tmp.begin() + static_cast<std::ptrdiff_t>(tmp.size() / 2);
  std::nth_element(tmp.begin(), mid, tmp.end());
  return *mid;
}

void estimateBackground(const cv::Mat& image, int tile, int samples, double sigma_floor,
                        BackgroundModel& m) {
  CV_Assert(image.channels() == 1 && (image.depth() == CV_8U || image.depth() == CV_16U));
  const double floor = std::max(sigma_floor, 0.3);
  thread_local std::vector<float> buf;
  if (tile <= 0 || (tile >= image.cols && tile >= image.rows)) {
    m.tile = m.tiles_x = m.tiles_y = 0;
    m.tile_level.clear();
    m.tile_sigma.clear();
    sampleAny(image, samples * 16, buf);
    robustLevelSigma(buf, m.level, m.sigma);
    m.sigma = std::max(m.sigma, floor);
    return;
  }
  m.tile = tile;
  m.tiles_x = (image.cols + tile - 1) / tile;
  m.tiles_y = (image.rows + tile - 1) / tile;
  m.tile_level.resize(static_cast<std::size_t>(m.tiles_x * m.tiles_y));
  m.tile_sigma.resize(m.tile_level.size());
  for (int ty = 0; ty < m.tiles_y; ++ty)
    for (int tx = 0; tx < m.tiles_x; ++tx) {
      const cv::Rect r(tx * tile, ty * tile, std::min(tile, image.cols - tx * tile),
                       std::min(tile, image.rows - ty * tile));
      sampleAny(image(r), samples, buf);
      double lv, sg;
      robustLevelSigma(buf, lv, sg);
      const std::size_t k = static_cast<std::size_t>(ty * m.tiles_x + tx);
      m.tile_level[k] = static_cast<float>(lv);
      m.tile_sigma[k] = static_cast<float>(std::max(sg, floor));
    }
  m.level = medianOf(m.tile_level, buf);
  m.sigma = medianOf(m.tile_sigma, buf);
}

}  // namespace st

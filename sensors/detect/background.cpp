#include "sensors/detect/background.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>

namespace st {
namespace {

// A tile whose IQR sigma exceeds its pixel-to-pixel noise by more than this holds structure
// (gradient, edge), not just noise. Pure noise gives a ratio near 1: both estimates come from
// 256 samples, each about 8 % uncertain (1.36 / sqrt(n) for the IQR), so 1.3 is > 3 sigma of
// their ratio.
constexpr double kStructureRatio = 1.3;

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

// Differences of horizontally adjacent pixels on the same grid as sample(): a smooth gradient
// or an edge across the ROI leaves them (almost all) at the noise, sqrt(2) sigma wide.
template <typename T>
void sampleDiffs(const cv::Mat& roi, int n, std::vector<float>& out) {
  out.clear();
  const double area = static_cast<double>(roi.rows) * roi.cols;
  const int stride = std::max(1, static_cast<int>(std::sqrt(area / std::max(n, 1))));
  for (int r = stride / 2; r < roi.rows; r += stride) {
    const T* row = roi.ptr<T>(r);
    for (int c = ((r / stride) & 1) ? stride / 2 : 0; c + 1 < roi.cols; c += stride)
      out.push_back(static_cast<float>(row[c + 1]) - static_cast<float>(row[c]));
  }
}

// Noise sigma of the ROI from adjacent-pixel differences (0 when there are too few).
double diffSigma(const cv::Mat& roi, int n, std::vector<float>& buf) {
  if (roi.depth() == CV_8U)
    sampleDiffs<uint8_t>(roi, n, buf);
  else
    sampleDiffs<uint16_t>(roi, n, buf);
  if (buf.size() < 24) return 0;
  double level = 0, sigma = 0;
  int q = 1;
  robustLevelSigma(buf, level, sigma, &q);
  // A difference of two grouped values spreads over two rounding intervals: variance
  // 2 (s^2 + q^2/12) + q^2/12 in the grouped reading, for the s^2 + q^2/12 of one pixel.
  const double qd = q;  // a step can be tens of thousands of ADU: its square overflows an int
  return std::sqrt(std::max(sigma * sigma - qd * qd / 12.0, 0.0) / 2.0);
}

double bilinear(const BackgroundModel& m, const std::vector<float>& t, double x, double y,
                bool extrapolate) {
  // Tile centres at (k + 0.5) * tile - 0.5. Outside the outer centres: the outer values held
  // (a flat sky: extrapolating would only amplify their noise), or with a gradient the
  // outer cells' planes extended (a glow keeps rising towards the border).
  double fx = (x + 0.5) / m.tile - 0.5, fy = (y + 0.5) / m.tile - 0.5;
  if (!extrapolate || m.tiles_x < 2) fx = std::clamp(fx, 0.0, m.tiles_x - 1.0);
  if (!extrapolate || m.tiles_y < 2) fy = std::clamp(fy, 0.0, m.tiles_y - 1.0);
  const int x0 = std::clamp(static_cast<int>(std::floor(fx)), 0, std::max(m.tiles_x - 2, 0));
  const int y0 = std::clamp(static_cast<int>(std::floor(fy)), 0, std::max(m.tiles_y - 2, 0));
  const int x1 = std::min(x0 + 1, m.tiles_x - 1), y1 = std::min(y0 + 1, m.tiles_y - 1);
  const double ax = fx - x0, ay = fy - y0;
  auto at = [&](int i, int j) { return static_cast<double>(t[static_cast<std::size_t>(j * m.tiles_x + i)]); };
  return (1 - ay) * ((1 - ax) * at(x0, y0) + ax * at(x1, y0)) +
         ay * ((1 - ax) * at(x0, y1) + ax * at(x1, y1));
}

}  // namespace

namespace {
// Quantisation step of the samples: the greatest common divisor of their differences. An ADC
// of b bits whose values are shifted into a 16-bit word counts in steps of 2^(16-b) (the tetra3
// frames step by 16); an 8-bit frame converted to 16 bits steps by 256 or 257 (x257 maps 255
// to 65535). 1 for too few samples to tell, 0 if some sample is not a whole number.
int32_t quantisationStep(const std::vector<float>& v) {
  if (v.empty()) return 1;
  bool whole = true;
  for (float x : v) {
    const bool in_range = std::abs(x) < 1e9f;
    whole &= in_range && static_cast<float>(static_cast<int32_t>(x)) == x;
  }
  if (!whole) return 0;
  // All of n noise samples share a factor g > 1 by chance with probability <= 2^-(n-1): trust
  // it only for a long list.
  if (v.size() < 24) return 1;
  const int32_t first = static_cast<int32_t>(v[0]);
  int32_t g = 0;
  for (float x : v) {
    int32_t a = std::abs(static_cast<int32_t>(x) - first);
    while (a != 0) {  // Euclid: g = gcd(g, a)
      const int32_t t = g % a;
      g = a;
      a = t;
    }
    if (g == 1) return 1;  // noise: usually within the first few samples
  }
  return g == 0 ? 1 : g;
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
int32_t groupedQuantiles(std::vector<float>& v, const double (&p)[3], double (&q)[3]) {
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
    // (x - lo) is a whole multiple of the step: rounding the quotient gives it exactly.
    const float inv_step = 1.0f / static_cast<float>(step);
    thread_local std::vector<uint32_t> count;
    count.assign(bins + 1, 0);  // the last: overflow
    for (float x : v)
      ++count[std::min(static_cast<std::size_t>((x - lo) * inv_step + 0.5f), bins)];
    std::size_t bin = 0, below = 0;
    int i = 0;
    for (; i < 3; ++i) {
      while (bin < bins && below + count[bin] <= k[i]) below += count[bin++];
      if (bin == bins) break;  // in the overflow: select instead
      q[i] = interpolateGroup(lo + static_cast<double>(bin) * step, step, target[i], below,
                              count[bin]);
    }
    if (i == 3) return step;
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
  return step;
}
}  // namespace

void robustLevelSigma(std::vector<float>& v, double& level, double& sigma, int* step) {
  // Median and interquartile range of the grouped data; IQR = 1.349 sigma for a Gaussian.
  // For Gaussian noise of sigma s rounded to integers the grouped quantiles are those of the
  // noise spread over the rounding interval, variance s^2 + 1/12: exactly the per-pixel
  // variance (noise + quantisation, seed 004 eq. 3.12) that the centroiders need.
  double q[3];
  const int32_t st = groupedQuantiles(v, {0.25, 0.5, 0.75}, q);
  if (step) *step = st;
  level = q[1];
  sigma = (q[2] - q[0]) / 1.349;
}

double BackgroundModel::levelAt(double x, double y) const {
  return tile > 0 ? bilinear(*this, tile_level, x, y, gradient) : level;
}
double BackgroundModel::sigmaAt(double x, double y) const {
  // Held, never extrapolated: the noise does not follow a glow's curve closely enough to
  // extend it safely (an extrapolated sigma near 0 would put the threshold on the level).
  return tile > 0 ? bilinear(*this, tile_sigma, x, y, false) : sigma;
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

namespace {
void estimateTiles(const cv::Mat& image, int tile, int samples, double floor, BackgroundModel& m);
}  // namespace

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
    robustLevelSigma(buf, m.level, m.sigma, &m.step);
    m.step = std::max(m.step, 1);
    m.sigma = std::max(m.sigma, floor);
    m.gradient = false;
    return;
  }
  estimateTiles(image, tile, samples, floor, m);
  m.gradient = hasGradient(m, kMaxTileChangeSigma);
  if (m.gradient && tile > kGradientTilePx) {
    estimateTiles(image, kGradientTilePx, std::max(16, samples / 4), floor, m);
    m.gradient = true;
  }
}

namespace {
void estimateTiles(const cv::Mat& image, int tile, int samples, double floor, BackgroundModel& m) {
  thread_local std::vector<float> buf;
  m.step = 0;
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
      int step = 1;
      robustLevelSigma(buf, lv, sg, &step);
      m.step = std::gcd(m.step, step);
      // A gradient (sky glow, twilight) or an edge (roof, trees) across the tile widens the
      // spread of its values but not the pixel-to-pixel noise: then the noise is read from the
      // differences of neighbouring pixels (the level follows the gradient by interpolation).
      if (sg > 0) {
        const double ds = diffSigma(image(r), samples, buf);
        if (ds > 0 && sg > kStructureRatio * ds) sg = ds;
      }
      const std::size_t k = static_cast<std::size_t>(ty * m.tiles_x + tx);
      m.tile_level[k] = static_cast<float>(lv);
      m.tile_sigma[k] = static_cast<float>(std::max(sg, floor));
    }
  m.step = std::max(m.step, 1);
  m.level = medianOf(m.tile_level, buf);
  m.sigma = medianOf(m.tile_sigma, buf);
}
}  // namespace

bool hasGradient(const BackgroundModel& m, double max_change_sigma) {
  if (m.tile <= 0) return false;
  auto at = [&](const std::vector<float>& t, int i, int j) {
    return static_cast<double>(t[static_cast<std::size_t>(j * m.tiles_x + i)]);
  };
  for (int j = 0; j < m.tiles_y; ++j)
    for (int i = 0; i < m.tiles_x; ++i) {
      const double l = at(m.tile_level, i, j), s = at(m.tile_sigma, i, j);
      if (i + 1 < m.tiles_x && std::abs(at(m.tile_level, i + 1, j) - l) >
                                   max_change_sigma * std::min(s, at(m.tile_sigma, i + 1, j)))
        return true;
      if (j + 1 < m.tiles_y && std::abs(at(m.tile_level, i, j + 1) - l) >
                                   max_change_sigma * std::min(s, at(m.tile_sigma, i, j + 1)))
        return true;
    }
  return false;
}

void thresholdMask(const cv::Mat& grey, const BackgroundModel& m, double k, cv::Mat& map,
                   cv::Mat& mask) {
  CV_Assert(m.tile > 0 && grey.channels() == 1 &&
            (grey.depth() == CV_8U || grey.depth() == CV_16U));
  // levelAt + k sigmaAt row by row: per row, the value at each tile column's centre, then
  // linear along the row between (and beyond) them.
  thread_local std::vector<double> lv, sv;
  thread_local std::vector<int> col_i0;
  thread_local std::vector<float> col_a, col_as;
  lv.resize(static_cast<std::size_t>(m.tiles_x));
  sv.resize(lv.size());
  map.create(1, grey.cols, CV_32F);
  mask.create(grey.size(), CV_8U);
  const int last = std::max(m.tiles_x - 2, 0);
  // Where each column sits between tile centres does not depend on the row: once per call
  // (the per-pixel floor and clamps were most of the detector's time on a graded frame).
  col_i0.resize(static_cast<std::size_t>(grey.cols));
  col_a.resize(col_i0.size());
  col_as.resize(col_i0.size());
  for (int x = 0; x < grey.cols; ++x) {
    const double fx = (x + 0.5) / m.tile - 0.5;
    const int i0 = std::clamp(static_cast<int>(std::floor(fx)), 0, last);
    const double a = m.tiles_x < 2 ? 0.0 : fx - i0;
    col_i0[static_cast<std::size_t>(x)] = i0;
    col_as[static_cast<std::size_t>(x)] = static_cast<float>(std::clamp(a, 0.0, 1.0));  // sigma held beyond the outer centres
    col_a[static_cast<std::size_t>(x)] = m.gradient ? static_cast<float>(a) : col_as[static_cast<std::size_t>(x)];
  }
  thread_local std::vector<float> l0, dl, s0, ds;
  l0.resize(lv.size()), dl.resize(lv.size()), s0.resize(lv.size()), ds.resize(lv.size());
  for (int y = 0; y < grey.rows; ++y) {
    for (int i = 0; i < m.tiles_x; ++i) {
      const double cx = (i + 0.5) * m.tile - 0.5;  // the centre column: exact there
      lv[static_cast<std::size_t>(i)] = m.levelAt(cx, y);
      sv[static_cast<std::size_t>(i)] = m.sigmaAt(cx, y);
    }
    for (int i = 0; i < m.tiles_x; ++i) {
      const std::size_t i0 = static_cast<std::size_t>(i), i1 = static_cast<std::size_t>(std::min(i + 1, m.tiles_x - 1));
      l0[i0] = static_cast<float>(lv[i0]);
      dl[i0] = static_cast<float>(lv[i1] - lv[i0]);
      s0[i0] = static_cast<float>(k * sv[i0]);
      ds[i0] = static_cast<float>(k * (sv[i1] - sv[i0]));
    }
    float* row = map.ptr<float>(0);
    for (int x = 0; x < grey.cols; ++x) {
      const std::size_t i0 = static_cast<std::size_t>(col_i0[static_cast<std::size_t>(x)]);
      row[x] = l0[i0] + col_a[static_cast<std::size_t>(x)] * dl[i0] + s0[i0] +
               col_as[static_cast<std::size_t>(x)] * ds[i0];
    }
    uint8_t* out = mask.ptr<uint8_t>(y);
    if (grey.depth() == CV_8U) {
      const uint8_t* g = grey.ptr<uint8_t>(y);
      for (int x = 0; x < grey.cols; ++x) out[x] = g[x] > row[x] ? 255 : 0;
    } else {
      const uint16_t* g = grey.ptr<uint16_t>(y);
      for (int x = 0; x < grey.cols; ++x) out[x] = g[x] > row[x] ? 255 : 0;
    }
  }
}

}  // namespace st

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
// Quantile p of integer-valued samples read as grouped data: each value k stands for the
// interval [k - 0.5, k + 0.5) (what the ADC rounded), and the quantile is interpolated inside
// its interval. The plain order statistic of quantised data is itself an integer: a median
// off by up to 0.5 ADU and a MAD of 0 or 1 ADU when sigma ~ 1 ADU (8-bit cameras), i.e. a
// background bias and a noise estimate off by up to 40 %.
// Pixel values are integers of small spread (background noise): a counting sort is O(n +
// range) and branch-free, where a comparison sort of noise mispredicts nearly every branch
// (this runs for every tracking window's border ring).
void sortSamples(std::vector<float>& v) {
  // Beyond a few counters per sample, clearing and scanning the counters costs more.
  const float max_range = static_cast<float>(std::max<std::size_t>(64, 2 * v.size()));
  float lo = v.front(), hi = v.front();
  bool integer = true;
  for (float x : v) {
    lo = std::min(lo, x);
    hi = std::max(hi, x);
    integer = integer && x == std::floor(x);
  }
  if (!integer || hi - lo > max_range) {
    std::sort(v.begin(), v.end());
    return;
  }
  thread_local std::vector<uint32_t> count;
  count.assign(static_cast<std::size_t>(hi - lo) + 1, 0);
  for (float x : v) ++count[static_cast<std::size_t>(x - lo)];
  auto out = v.begin();
  for (std::size_t k = 0; k < count.size(); ++k)
    out = std::fill_n(out, count[k], lo + static_cast<float>(k));
}

double groupedQuantile(const std::vector<float>& sorted, double p) {
  const double target = p * static_cast<double>(sorted.size());
  const std::size_t k = std::min(sorted.size() - 1, static_cast<std::size_t>(target));
  const float m = sorted[k];
  if (m != std::floor(m)) return m;  // not integer data: the order statistic
  const auto [lo, hi] = std::equal_range(sorted.begin(), sorted.end(), m);
  const double below = static_cast<double>(lo - sorted.begin());
  return m - 0.5 + (target - below) / static_cast<double>(hi - lo);
}
}  // namespace

void robustLevelSigma(std::vector<float>& v, double& level, double& sigma) {
  // Median and interquartile range of the grouped data; IQR = 1.349 sigma for a Gaussian.
  // For Gaussian noise of sigma s rounded to integers the grouped quantiles are those of the
  // noise spread over the rounding interval, variance s^2 + 1/12: exactly the per-pixel
  // variance (noise + quantisation, seed 004 eq. 3.12) that the centroiders need.
  sortSamples(v);  // one sort for the three quantiles
  level = groupedQuantile(v, 0.5);
  sigma = (groupedQuantile(v, 0.75) - groupedQuantile(v, 0.25)) / 1.349;
}

double BackgroundModel::levelAt(double x, double y) const {
  return tile > 0 ? bilinear(*this, tile_level, x, y) : level;
}
double BackgroundModel::sigmaAt(double x, double y) const {
  return tile > 0 ? bilinear(*this, tile_sigma, x, y) : sigma;
}

BackgroundModel estimateBackground(const cv::Mat& image, int tile, int samples,
                                   double sigma_floor) {
  CV_Assert(image.channels() == 1 && (image.depth() == CV_8U || image.depth() == CV_16U));
  const double floor = std::max(sigma_floor, 0.3);
  BackgroundModel m;
  thread_local std::vector<float> buf;
  if (tile <= 0 || (tile >= image.cols && tile >= image.rows)) {
    sampleAny(image, samples * 16, buf);
    robustLevelSigma(buf, m.level, m.sigma);
    m.sigma = std::max(m.sigma, floor);
    return m;
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
  std::vector<float> tmp = m.tile_level;
  std::nth_element(tmp.begin(), tmp.begin() + static_cast<std::ptrdiff_t>(tmp.size() / 2), tmp.end());
  m.level = tmp[tmp.size() / 2];
  tmp = m.tile_sigma;
  std::nth_element(tmp.begin(), tmp.begin() + static_cast<std::ptrdiff_t>(tmp.size() / 2), tmp.end());
  m.sigma = tmp[tmp.size() / 2];
  return m;
}

}  // namespace st

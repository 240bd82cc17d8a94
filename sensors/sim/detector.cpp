#include "sensors/sim/detector.hpp"

#include <algorithm>
#include <cmath>

#include "common/errors.hpp"
#include "sensors/sim/random_streams.hpp"

namespace st {

namespace {
double normalCdf(double z) { return 0.5 * std::erfc(-z / std::sqrt(2.0)); }
}  // namespace

Detector::Detector(const SensorParams& params, int width, int height)
    : p_(params), width_(width), height_(height), base_level_(params.backgroundElectrons()) {
  p_.validate("detector");
  if (width <= 0 || height <= 0) throw InputError("detector: image size must be positive");
  // Hot pixels are a property of the chip: drawn from their own seed, distinct positions.
  std::mt19937_64 rng(streamSeed(p_.hot_pixel_seed, RandomStream::kFaultLayout, 0xC0FFEE));
  std::uniform_int_distribution<int> ux(0, width - 1), uy(0, height - 1);
  const int n = std::min<long long>(p_.hot_pixels, static_cast<long long>(width) * height / 4);
  std::vector<char> used(static_cast<std::size_t>(width) * height, 0);
  while (static_cast<int>(hot_.size()) < n) {
    const cv::Point pt(ux(rng), uy(rng));
    char& u = used[static_cast<std::size_t>(pt.y) * width + pt.x];
    if (u) continue;
    u = 1;
    hot_.push_back(pt);
  }
  buildBaseTable();
}

cv::Mat Detector::meanBackground() const {
  cv::Mat m(height_, width_, CV_64FC1, cv::Scalar(base_level_));
  const double extra = p_.hot_pixel_e_px_s * p_.exposure_s;
  for (const cv::Point& pt : hot_) m.at<double>(pt) += extra;
  return m;
}

int Detector::toAdu(double electrons) const {
  // Quantisation (eq. 3.12): round to the nearest ADU, then the ADC range.
  const double x = std::floor(electrons / p_.gain() + p_.bias_adu + 0.5);
  return static_cast<int>(std::clamp(x, 0.0, static_cast<double>(p_.maxAdu())));
}

void Detector::buildBaseTable() {
  const double lam = base_level_, g = p_.gain(), R = p_.read_noise_e;
  const double spread = 12.0 * std::sqrt(lam) + 12.0;
  const long long n_lo = std::max(0LL, static_cast<long long>(std::floor(lam - spread)));
  const long long n_hi = static_cast<long long>(std::ceil(lam + spread));
  const int k_lo = toAdu(std::min<double>(n_lo, p_.full_well_e) - 12.0 * R - g);
  const int k_hi = toAdu(std::min<double>(n_hi, p_.full_well_e) + 12.0 * R + g);
  table_first_adu_ = k_lo;
  std::vector<double> prob(static_cast<std::size_t>(k_hi - k_lo + 1), 0.0);
  for (long long n = n_lo; n <= n_hi; ++n) {
    // Poisson pmf of the collected electrons (eqs. 3.7, 3.8), via logs for large lambda.
    const double pn = lam > 0 ? std::exp(n * std::log(lam) - lam - std::lgamma(n + 1.0))
                              : (n == 0 ? 1.0 : 0.0);
    if (pn < 1e-300) continue;
    const double e = std::min<double>(static_cast<double>(n), p_.full_well_e);
    if (R <= 0) {
      prob[static_cast<std::size_t>(toAdu(e) - k_lo)] += pn;
      continue;
    }
    // Read noise (eq. 3.14) then rounding: ADU k collects e + r in [(k-0.5-bias) g, (k+0.5-bias) g).
    for (int k = k_lo; k <= k_hi; ++k) {
      const double lo = k == 0 ? -INFINITY : ((k - 0.5 - p_.bias_adu) * g - e) / R;
      const double hi = k == p_.maxAdu() ? INFINITY : ((k + 0.5 - p_.bias_adu) * g - e) / R;
      prob[static_cast<std::size_t>(k - k_lo)] += pn * (normalCdf(hi) - normalCdf(lo));
    }
  }
  double total = 0;
  for (double v : prob) total += v;
  // Vose's alias method.
  const std::size_t K = prob.size();
  std::vector<double> scaled(K);
  std::vector<std::size_t> small, large;
  for (std::size_t i = 0; i < K; ++i) {
    scaled[i] = prob[i] / total * static_cast<double>(K);
    (scaled[i] < 1.0 ? small : large).push_back(i);
  }
  alias_prob_.assign(K, 0xFFFFFFFFu);
  alias_other_.resize(K);
  for (std::size_t i = 0; i < K; ++i) alias_other_[i] = static_cast<uint32_t>(i);
  while (!small.empty() && !large.empty()) {
    const std::size_t s = small.back(), l = large.back();
    small.pop_back();
    alias_prob_[s] = static_cast<uint32_t>(std::min(scaled[s] * 4294967296.0, 4294967295.0));
    alias_other_[s] = static_cast<uint32_t>(l);
    scaled[l] -= 1.0 - scaled[s];
    if (scaled[l] < 1.0) {
      large.pop_back();
      small.push_back(l);
    }
  }
}

cv::Mat Detector::expose(const cv::Mat& mean_electrons, std::mt19937_64& rng) const {
  CV_Assert(mean_electrons.type() == CV_64FC1 && mean_electrons.rows == height_ &&
            mean_electrons.cols == width_);
  const bool eight = p_.bit_depth == 8;
  cv::Mat out(height_, width_, eight ? CV_8UC1 : CV_16UC1);
  const double g = p_.gain(), R = p_.read_noise_e;
  const uint64_t K = alias_prob_.size();
  std::normal_distribution<double> read(0.0, 1.0);
  for (int y = 0; y < height_; ++y) {
    const double* lam = mean_electrons.ptr<double>(y);
    uint8_t* o8 = eight ? out.ptr<uint8_t>(y) : nullptr;
    uint16_t* o16 = eight ? nullptr : out.ptr<uint16_t>(y);
    for (int x = 0; x < width_; ++x) {
      int adu;
      if (lam[x] == base_level_) {
        const uint64_t u = rng();
        const uint64_t i = ((u >> 32) * K) >> 32;
        const uint32_t thr = static_cast<uint32_t>(u);
        adu = table_first_adu_ + static_cast<int>(thr < alias_prob_[i] ? i : alias_other_[i]);
      } else {
        double n = 0;
        if (lam[x] > 0) n = static_cast<double>(std::poisson_distribution<long long>(lam[x])(rng));
        n = std::min(n, p_.full_well_e);
        if (R > 0) n += R * read(rng);
        adu = static_cast<int>(std::clamp(std::floor(n / g + p_.bias_adu + 0.5), 0.0,
                                          static_cast<double>(p_.maxAdu())));
      }
      if (eight)
        o8[x] = static_cast<uint8_t>(adu);
      else
        o16[x] = static_cast<uint16_t>(adu);
    }
  }
  return out;
}

cv::Mat Detector::exposeNoiseless(const cv::Mat& mean_electrons) const {
  CV_Assert(mean_electrons.type() == CV_64FC1);
  const bool eight = p_.bit_depth == 8;
  cv::Mat out(mean_electrons.rows, mean_electrons.cols, eight ? CV_8UC1 : CV_16UC1);
  for (int y = 0; y < out.rows; ++y)
    for (int x = 0; x < out.cols; ++x) {
      const int adu = toAdu(std::min(mean_electrons.at<double>(y, x), p_.full_well_e));
      if (eight)
        out.at<uint8_t>(y, x) = static_cast<uint8_t>(adu);
      else
        out.at<uint16_t>(y, x) = static_cast<uint16_t>(adu);
    }
  return out;
}

}  // namespace st

/// @file detector.hpp
/// The simulated detector: turns an image of MEAN electrons per pixel into a digitised
/// frame with Poisson shot noise, read noise, full-well clipping, gain, bias, quantisation
/// and ADC clipping (model and equations in sensor_params.hpp). It also owns the fixed
/// hot-pixel map of the camera.
///
/// Speed: most pixels of a star image hold only sky + dark current, the same mean λ0. For
/// them the exact distribution of the output ADU value (Poisson ⊗ Gaussian read noise,
/// clipped, scaled, rounded, clipped) is tabulated once and sampled with Walker's alias
/// method, one 64-bit random number per pixel. Every other pixel (stars, hot pixels, a
/// blinding glow) is drawn the direct way: Poisson, then Gaussian. Both give the same
/// distribution; tests/sim check the table path against the model.
#pragma once
#include <cstdint>
#include <opencv2/core.hpp>
#include <random>
#include <vector>

#include "sensors/sim/sensor_params.hpp"

namespace st {

class Detector {
 public:
  Detector(const SensorParams& params, int width, int height);

  const SensorParams& params() const { return p_; }
  int width() const { return width_; }
  int height() const { return height_; }

  /// Mean electrons per pixel before any source: sky + dark everywhere, plus the hot
  /// pixels' extra dark current (CV_64F). The renderer adds signal to a copy of it.
  cv::Mat meanBackground() const;
  /// Mean electrons of a plain pixel (sky + dark), the value the fast path is built for.
  double baseLevel() const { return base_level_; }
  /// Fixed hot-pixel positions (x = column, y = row).
  const std::vector<cv::Point>& hotPixels() const { return hot_; }

  /// One noisy exposure of `mean_electrons` (CV_64F, width x height): CV_8U when
  /// bit_depth == 8, else CV_16U.
  cv::Mat expose(const cv::Mat& mean_electrons, std::mt19937_64& rng) const;
  /// The same without noise: full-well clip, gain, bias, round, ADC clip.
  cv::Mat exposeNoiseless(const cv::Mat& mean_electrons) const;

 private:
  int toAdu(double electrons) const;
  void buildBaseTable();

  SensorParams p_;
  int width_, height_;
  double base_level_;
  std::vector<cv::Point> hot_;
  // Alias table of the ADU distribution of a pixel with mean base_level_.
  int table_first_adu_ = 0;
  std::vector<uint32_t> alias_prob_;  // acceptance threshold * 2^32
  std::vector<uint32_t> alias_other_;
};

}  // namespace st

/// @file background.hpp
/// Robust background level and noise of a star image (seed 004 §4.1): the median and the
/// median absolute deviation (sigma = 1.4826 MAD) of a regular subsample of the pixels,
/// either for the whole frame or per tile (sky gradients, vignetting, light pollution).
/// Stars cover a small fraction of the pixels, so they barely move the median.
#pragma once
#include <vector>

#include <opencv2/core.hpp>

namespace st {

struct BackgroundModel {
  double level = 0;  ///< [ADU] global (median of the tile levels when tiled)
  double sigma = 0;  ///< [ADU] global noise
  int tile = 0;      ///< tile side [px]; 0 = global only
  int tiles_x = 0, tiles_y = 0;
  std::vector<float> tile_level, tile_sigma;  ///< row-major tiles_y x tiles_x

  /// Level and sigma at pixel (x, y): bilinear between tile centres, or the global values.
  double levelAt(double x, double y) const;
  double sigmaAt(double x, double y) const;
};

/// `image`: CV_8UC1 or CV_16UC1. `tile` 0 = global; `samples` pixels per tile (globally 16x
/// that). `sigma_floor` [ADU] lower bound on the sigma (read noise; at least 0.3 ADU, the
/// quantisation noise, so a flat frame still has a threshold above its level).
BackgroundModel estimateBackground(const cv::Mat& image, int tile, int samples,
                                   double sigma_floor);
/// The same into `out`, reusing its tile vectors (no allocation frame after frame).
void estimateBackground(const cv::Mat& image, int tile, int samples, double sigma_floor,
                        BackgroundModel& out);

/// Median and IQR / 1.349 of the samples `v` (non-empty; reordered), read as grouped data:
/// whole-number samples stand for their rounding interval, whose width is the quantisation
/// step found in the data (a power of two: 12-bit pixels shifted into 16 bits step by 16), so
/// that scaling the samples by the step scales both results by it.
void robustLevelSigma(std::vector<float>& v, double& level, double& sigma);

}  // namespace st

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
  /// Quantisation step of the pixel values [ADU] (1 unless every sample is a multiple of a
  /// larger one, e.g. 16 for 12-bit data in a 16-bit word, 257 for an 8-bit frame x257).
  int step = 1;
  /// The level changes between neighbouring tiles by more than their noise (sky glow,
  /// twilight, the Moon, a foreground edge): the tiles are then finer (estimateBackground),
  /// levelAt / sigmaAt extrapolate linearly beyond the outer tile centres instead of holding
  /// the outer values, and the threshold follows them pixel by pixel (thresholdMask).
  bool gradient = false;

  /// Level and sigma at pixel (x, y): bilinear between tile centres (see `gradient` for
  /// beyond them), or the global values.
  double levelAt(double x, double y) const;
  double sigmaAt(double x, double y) const;
};

/// `image`: CV_8UC1 or CV_16UC1. `tile` 0 = global; `samples` pixels per tile (globally 16x
/// that). When the tiles show a gradient (hasGradient), the estimate is redone on tiles of
/// kGradientTilePx with samples / 4 each, which follow a skyline or a curved glow closer. `sigma_floor` [ADU] lower bound on the sigma (read noise; at least 0.3 ADU, the
/// quantisation noise, so a flat frame still has a threshold above its level).
BackgroundModel estimateBackground(const cv::Mat& image, int tile, int samples,
                                   double sigma_floor);
/// The same into `out`, reusing its tile vectors (no allocation frame after frame).
void estimateBackground(const cv::Mat& image, int tile, int samples, double sigma_floor,
                        BackgroundModel& out);

/// Median and IQR / 1.349 of the samples `v` (non-empty; reordered), read as grouped data:
/// whole-number samples stand for their rounding interval, whose width is the quantisation
/// step found in the data (the greatest common divisor of their differences: 12-bit pixels
/// shifted into 16 bits step by 16, an 8-bit frame written as 16 bits by 256 or 257), so
/// that scaling the samples by the step scales both results by it. `step`, when given,
/// receives that step (1 when the samples do not tell, 0 for samples that are not whole).
void robustLevelSigma(std::vector<float>& v, double& level, double& sigma,
                      int* step = nullptr);

/// Whether the tiled level changes between neighbouring tiles by more than
/// `max_change_sigma` of their noise (a gradient of sky glow, twilight, the Moon, or a
/// foreground edge): then a threshold constant per tile would be off by half that at the tile
/// borders, and the threshold must follow the interpolated level pixel by pixel.
bool hasGradient(const BackgroundModel& m, double max_change_sigma);
/// Neighbouring tiles whose levels differ by more than this many sigmas: a gradient.
constexpr double kMaxTileChangeSigma = 1.0;
/// Tile side [px] of a background with a gradient.
constexpr int kGradientTilePx = 32;

/// `mask` (CV_8U, 0/255) = grey > levelAt(x, y) + k sigmaAt(x, y) at every pixel. `map` is
/// scratch. Needs a tiled model.
void thresholdMask(const cv::Mat& grey, const BackgroundModel& m, double k, cv::Mat& map,
                   cv::Mat& mask);

}  // namespace st

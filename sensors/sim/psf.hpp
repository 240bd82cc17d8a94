/// @file psf.hpp
/// The Gaussian point-spread function integrated over each pixel (not sampled at its
/// centre): the fraction of a star's light that falls on pixel (i, j) is
///   [Phi((i+0.5-x)/s) - Phi((i-0.5-x)/s)] * [Phi((j+0.5-y)/s) - Phi((j-0.5-y)/s)]
/// with Phi the standard normal CDF. Shared by the simulator and by tests of detection.
#pragma once
#include <opencv2/core.hpp>

#include "common/attitude.hpp"

namespace st {

/// Adds `total` (electrons or any unit) of a star centred at pixel `px` with Gaussian PSF
/// standard deviation `sigma_px` to `image` (CV_64F, one channel). Pixels farther than
/// `radius_sigmas` * sigma are skipped (their share is below 1e-9 at the default 6).
/// Light falling outside the image is lost, as on a real detector.
void addGaussianStar(cv::Mat& image, const Vec2& px, double total, double sigma_px,
                     double radius_sigmas = 6.0);

/// The same with different sigmas along x and y (binned pixels, a radiation hit's diffusion).
void addGaussianStarXY(cv::Mat& image, const Vec2& px, double total, double sigma_x,
                       double sigma_y, double radius_sigmas = 6.0);

/// Fraction of a pixel-integrated Gaussian falling on the pixel interval [a-0.5, a+0.5]
/// along one axis, for a centre x and sigma s.
double pixelFraction1d(double a, double x, double s);

}  // namespace st

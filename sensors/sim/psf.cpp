#include "sensors/sim/psf.hpp"

#include <cmath>
#include <vector>

namespace st {

double pixelFraction1d(double a, double x, double s) {
  const double k = 1.0 / (std::sqrt(2.0) * s);
  return 0.5 * (std::erf((a + 0.5 - x) * k) - std::erf((a - 0.5 - x) * k));
}

void addGaussianStar(cv::Mat& image, const Vec2& px, double total, double sigma_px,
                     double radius_sigmas) {
  addGaussianStarXY(image, px, total, sigma_px, sigma_px, radius_sigmas);
}

void addGaussianStarXY(cv::Mat& image, const Vec2& px, double total, double sigma_x,
                       double sigma_y, double radius_sigmas) {
  CV_Assert(image.type() == CV_64FC1);
  const double rx = radius_sigmas * sigma_x + 1.0, ry = radius_sigmas * sigma_y + 1.0;
  const int x0 = std::max(0, static_cast<int>(std::floor(px.x() - rx)));
  const int x1 = std::min(image.cols - 1, static_cast<int>(std::ceil(px.x() + rx)));
  const int y0 = std::max(0, static_cast<int>(std::floor(px.y() - ry)));
  const int y1 = std::min(image.rows - 1, static_cast<int>(std::ceil(px.y() + ry)));
  if (x0 > x1 || y0 > y1) return;
  // Separable: one erf pair per column and per row instead of per pixel.
  std::vector<double> fx(static_cast<std::size_t>(x1 - x0 + 1));
  for (int i = x0; i <= x1; ++i) fx[static_cast<std::size_t>(i - x0)] = pixelFraction1d(i, px.x(), sigma_x);
  for (int j = y0; j <= y1; ++j) {
    const double fy = total * pixelFraction1d(j, px.y(), sigma_y);
    double* row = image.ptr<double>(j);
    for (int i = x0; i <= x1; ++i) row[i] += fy * fx[static_cast<std::size_t>(i - x0)];
  }
}

}  // namespace st

// Spike rejection of the "gauss" fit: a pixel the round model cannot explain.
#include <algorithm>
#include <vector>

#include "sensors/detect/gauss_fit_internal.hpp"
#include "sensors/detect/pixel_gaussian.hpp"

namespace st::gauss_fit_detail {

// Marks the worst outlier pixel at p unusable: a single-pixel spike (a hot pixel, a cosmic
// ray) more than kOutlierSigma above the model (variance from the model, as the fit weighs
// it) and more than twice any of its four neighbours' excess, all of them usable. Only
// positive spikes: they add light. What the round model misses of a real star (a smear, an
// undersampled core: spread over neighbouring pixels) stays. Not safe on a star clipped at a
// saturation level the options do not know (read noise after the clip makes its flat top
// look like spikes of tens of sigma, measured): hence off by default (DetectorOptions).
bool dropOutlier(const StarPatch& P, const V5& p, Work& W) {
  pixelGaussianRow(W.cols, P.origin.x, p[0], p[4], W.fx.data(), W.dx.data(), W.sx.data());
  pixelGaussianRow(W.rows, P.origin.y, p[1], p[4], W.fy.data(), W.dy.data(), W.sy.data());
  const double sb2 = P.sigma_bg * P.sigma_bg, inv_gain = 1.0 / P.gain;
  const int rows = W.rows, cols = W.cols;
  thread_local std::vector<double> res, z2;
  res.assign(static_cast<std::size_t>(rows * cols), 0.0);
  z2.assign(res.size(), 0.0);  // zero where the pixel is not a candidate
  auto slot = [&](int r, int c) {  // pixel (r, c) in the interleaved buffers
    return static_cast<std::size_t>((r / kLanes) * cols * kLanes + r % kLanes + c * kLanes);
  };
  for (int r = 0; r < rows; ++r) {
    const double Ffy = p[2] * W.fy[static_cast<std::size_t>(r)];
    for (int c = 0; c < cols; ++c) {
      const std::size_t i = slot(r, c), k = static_cast<std::size_t>(r * cols + c);
      const double m = Ffy * W.fx[static_cast<std::size_t>(c)];
      res[k] = W.use[i] > 0 ? W.val[i] - p[3] - m : 0.0;
      z2[k] = res[k] > 0 ? res[k] * res[k] / (sb2 + std::max(m, 0.0) * inv_gain) : 0.0;
    }
  }
  double worst = kOutlierSigma * kOutlierSigma;
  int at = -1;
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      const std::size_t k = static_cast<std::size_t>(r * cols + c);
      if (!(z2[k] > worst)) continue;
      double nb = 0;
      bool usable = true;
      auto neighbour = [&](int rr, int cc) {
        if (rr < 0 || rr >= rows || cc < 0 || cc >= cols) return;
        nb = std::max(nb, res[static_cast<std::size_t>(rr * cols + cc)]);
        usable = usable && W.use[slot(rr, cc)] > 0;
      };
      neighbour(r - 1, c);
      neighbour(r + 1, c);
      neighbour(r, c - 1);
      neighbour(r, c + 1);
      if (usable && res[k] > 2.0 * nb) {
        worst = z2[k];
        at = r * cols + c;
      }
    }
  if (at < 0) return false;
  W.use[slot(at / cols, at % cols)] = 0;
  return true;
}

}  // namespace st::gauss_fit_detail

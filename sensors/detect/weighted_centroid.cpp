#include "sensors/detect/weighted_centroid.hpp"

#include <algorithm>
#include <cmath>

namespace st::detail {

bool weightedCentroid(const StarPatch& patch, const Vec2& start, double weight_sigma,
                      int max_iter, Centroid& out, std::string* reason) {
  const cv::Mat1f& v = patch.values;
  const bool flat = weight_sigma <= 0;
  const double inv_w2 = flat ? 0.0 : 1.0 / (weight_sigma * weight_sigma);
  const double ox = patch.origin.x, oy = patch.origin.y;
  Vec2 x = start;
  if (flat) max_iter = 1;
  for (int it = 0; it < max_iter; ++it) {
    // Seed 004 eq. 4.1: position = sum(S_i p_i) / sum(S_i), here with weights g_i.
    double sw = 0, sx = 0, sy = 0;
    for (int r = 0; r < v.rows; ++r) {
      const float* row = v[r];
      const double py = oy + r;
      for (int c = 0; c < v.cols; ++c) {
        const double s = row[c] - patch.background;
        const double px = ox + c;
        double g = 1.0;
        if (!flat) {
          const double dx = px - x.x(), dy = py - x.y();
          g = std::exp(-0.5 * (dx * dx + dy * dy) * inv_w2);
        }
        sw += g * s;
        sx += g * s * px;
        sy += g * s * py;
      }
    }
    if (!(sw > 0)) {
      if (reason) *reason = "no flux above background";
      return false;
    }
    const Vec2 nx(sx / sw, sy / sw);
    const double step = (nx - x).norm();
    x = nx;
    if (step < 1e-4 && it > 0) break;
  }
  if (x.x() < ox - 0.5 || x.y() < oy - 0.5 || x.x() > ox + v.cols - 0.5 ||
      x.y() > oy + v.rows - 0.5) {
    if (reason) *reason = "centroid left the window";
    return false;
  }
  // Linearised covariance of the fixed point (header), plus flux, peak and SNR.
  Mat2 J = Mat2::Zero(), M = Mat2::Zero();
  Vec2 Gd = Vec2::Zero();  // dF/db = -sum g_i d_i: the shift of a background error
  double flux = 0, peak = -1e300, var_flux = 0;
  for (int r = 0; r < v.rows; ++r) {
    const float* row = v[r];
    for (int c = 0; c < v.cols; ++c) {
      const double s = row[c] - patch.background;
      const Vec2 d(ox + c - x.x(), oy + r - x.y());
      const double g = flat ? 1.0 : std::exp(-0.5 * d.squaredNorm() * inv_w2);
      const double var = patch.variance(s);
      J += s * g * (d * d.transpose() * inv_w2 - Mat2::Identity());
      M += var * g * g * d * d.transpose();
      Gd += g * d;
      flux += s;
      var_flux += var;
      peak = std::max(peak, s);
    }
  }
  const double det = J.determinant();
  if (!(std::abs(det) > 0)) {
    if (reason) *reason = "degenerate weights";
    return false;
  }
  const Mat2 Ji = J.inverse();
  out.px = x;
  // A background error db shifts every s_i by -db: dF = -db sum g_i d_i, independent of the
  // per-pixel noise; zero for a window centred on the star, large for an off-centre one.
  out.cov_px = Ji * (M + patch.background_var * Gd * Gd.transpose()) * Ji.transpose();
  out.flux = flux;
  out.peak = peak;
  out.snr = flux / std::sqrt(std::max(var_flux, 1e-300));
  return true;
}

}  // namespace st::detail

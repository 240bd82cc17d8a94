#include "sensors/detect/weighted_centroid.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "common/cpu_clones.hpp"

namespace st::detail {

namespace {

// Flat weights (CoG) in one pass: with d_i = p_i - x the sums of the header expand into raw
// moments in window coordinates (small numbers, no cancellation), accumulated per row.
ST_AVX2_CLONES
bool flatCentroid(const StarPatch& patch, Centroid& out, std::string* reason) {
  const cv::Mat1f& v = patch.values;
  const double b = patch.background, var0 = patch.sigma_bg * patch.sigma_bg;
  // StarPatch::variance with the division hoisted: a division per pixel costs this loop,
  // which runs in every tracking window, a third of the frame time.
  const double inv_gain = 1.0 / patch.gain;
  double S0 = 0, Sx = 0, Sy = 0;                        // sum s, s c, s r
  double V0 = 0, Vx = 0, Vy = 0, Vxx = 0, Vxy = 0, Vyy = 0;  // sum var * (1, c, r, c^2, c r, r^2)
  double peak = -1e300;
  // Four columns at a time in separate partial sums (lanes): a reduction the compiler may
  // not reorder otherwise stays scalar, and this loop runs for every tracking window.
  constexpr int L = 4;
  for (int r = 0; r < v.rows; ++r) {
    const float* row = v[r];
    double s0[L] = {}, sx[L] = {}, v0[L] = {}, vx[L] = {}, vxx[L] = {}, pk[L];
    for (int j = 0; j < L; ++j) pk[j] = -1e300;
    int c = 0;
    for (; c + L <= v.cols; c += L) {
      for (int j = 0; j < L; ++j) {
        const double cc = c + j;
        const double s = row[c + j] - b;
        const double var = var0 + std::max(s, 0.0) * inv_gain;
        s0[j] += s;
        sx[j] += s * cc;
        v0[j] += var;
        vx[j] += var * cc;
        vxx[j] += var * cc * cc;
        pk[j] = std::max(pk[j], s);
      }
    }
    for (; c < v.cols; ++c) {  // the remainder in lane 0
      const double s = row[c] - b;
      const double var = var0 + std::max(s, 0.0) * inv_gain;
      s0[0] += s;
      sx[0] += s * c;
      v0[0] += var;
      vx[0] += var * c;
      vxx[0] += var * c * c;
      pk[0] = std::max(pk[0], s);
    }
    for (int j = 1; j < L; ++j) {
      s0[0] += s0[j], sx[0] += sx[j], v0[0] += v0[j], vx[0] += vx[j], vxx[0] += vxx[j];
      pk[0] = std::max(pk[0], pk[j]);
    }
    peak = std::max(peak, pk[0]);
    S0 += s0[0];
    Sx += sx[0];
    Sy += s0[0] * r;
    V0 += v0[0];
    Vx += vx[0];
    Vy += v0[0] * r;
    Vxx += vxx[0];
    Vxy += vx[0] * r;
    Vyy += v0[0] * r * r;
  }
  if (!(S0 > 0)) {
    if (reason) *reason = "no flux above background";
    return false;
  }
  const double cx = Sx / S0, cy = Sy / S0;  // window coordinates
  if (cx < -0.5 || cy < -0.5 || cx > v.cols - 0.5 || cy > v.rows - 0.5) {
    if (reason) *reason = "centroid left the window";
    return false;
  }
  // M = sum var d d^T with d = (c - cx, r - cy); J = -S0 I; Gd = sum d.
  Mat2 M;
  M(0, 0) = Vxx - 2 * cx * Vx + cx * cx * V0;
  M(1, 1) = Vyy - 2 * cy * Vy + cy * cy * V0;
  M(0, 1) = M(1, 0) = Vxy - cx * Vy - cy * Vx + cx * cy * V0;
  const double n = static_cast<double>(v.rows) * v.cols;
  const Vec2 Gd(n * (0.5 * (v.cols - 1) - cx), n * (0.5 * (v.rows - 1) - cy));
  out.px = Vec2(patch.origin.x + cx, patch.origin.y + cy);
  out.cov_px = (M + patch.background_var * Gd * Gd.transpose()) / (S0 * S0);
  out.flux = S0;
  out.peak = peak;
  out.snr = S0 / std::sqrt(std::max(V0, 1e-300));
  return true;
}

// The Gaussian weight is separable, g = gx(column) gy(row): rows + columns exponentials
// per pass instead of one per pixel (this runs in predictive windows).
struct SeparableWeights {
  double inv_w2;
  std::vector<double>& gx;
  std::vector<double>& gy;

  void at(const StarPatch& patch, const Vec2& x) {
    const cv::Mat1f& v = patch.values;
    const double ox = patch.origin.x, oy = patch.origin.y;
    for (int c = 0; c < v.cols; ++c)
      gx[static_cast<std::size_t>(c)] = std::exp(-0.5 * std::pow(ox + c - x.x(), 2) * inv_w2);
    for (int r = 0; r < v.rows; ++r)
      gy[static_cast<std::size_t>(r)] = std::exp(-0.5 * std::pow(oy + r - x.y(), 2) * inv_w2);
  }
  double operator()(int r, int c) const {
    return gx[static_cast<std::size_t>(c)] * gy[static_cast<std::size_t>(r)];
  }
};

// Seed 004 eq. 4.1: position = sum(S_i p_i) / sum(S_i), here with weights g_i, iterated
// from x (moved to the fixed point) until it moves less than 1e-4 px.
bool iterateWeighted(const StarPatch& patch, int max_iter, SeparableWeights& w, Vec2& x,
                     std::string* reason) {
  const cv::Mat1f& v = patch.values;
  const double ox = patch.origin.x, oy = patch.origin.y;
  for (int it = 0; it < max_iter; ++it) {
    w.at(patch, x);
    double sw = 0, sx = 0, sy = 0;
    for (int r = 0; r < v.rows; ++r) {
      const float* row = v[r];
      const double py = oy + r;
      for (int c = 0; c < v.cols; ++c) {
        const double s = row[c] - patch.background;
        const double px = ox + c;
        const double g = w(r, c);
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
  return true;
}

// Linearised covariance of the fixed point x (header), plus flux, peak and SNR.
bool fixedPointCovariance(const StarPatch& patch, const Vec2& x, SeparableWeights& w,
                          Centroid& out, std::string* reason) {
  const cv::Mat1f& v = patch.values;
  const double ox = patch.origin.x, oy = patch.origin.y, inv_w2 = w.inv_w2;
  // Scalar sums (2x2 symmetric matrices by their three entries): this loop runs for every
  // window of every tracked star.
  double sg = 0, jxx = 0, jxy = 0, jyy = 0;  // sum s g, sum s g d d^T
  double mxx = 0, mxy = 0, myy = 0;          // sum var g^2 d d^T
  double gdx = 0, gdy = 0;                   // dF/db = -sum g_i d_i: shift of a background error
  double flux = 0, peak = -1e300, var_flux = 0;
  w.at(patch, x);
  for (int r = 0; r < v.rows; ++r) {
    const float* row = v[r];
    const double dy = oy + r - x.y();
    for (int c = 0; c < v.cols; ++c) {
      const double s = row[c] - patch.background;
      const double dx = ox + c - x.x();
      const double g = w(r, c);
      const double var = patch.variance(s);
      const double sgi = s * g, vg2 = var * g * g;
      sg += sgi;
      jxx += sgi * dx * dx;
      jxy += sgi * dx * dy;
      jyy += sgi * dy * dy;
      mxx += vg2 * dx * dx;
      mxy += vg2 * dx * dy;
      myy += vg2 * dy * dy;
      gdx += g * dx;
      gdy += g * dy;
      flux += s;
      var_flux += var;
      peak = std::max(peak, s);
    }
  }
  Mat2 J, M;
  J << inv_w2 * jxx - sg, inv_w2 * jxy, inv_w2 * jxy, inv_w2 * jyy - sg;
  M << mxx, mxy, mxy, myy;
  const Vec2 Gd(gdx, gdy);
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

}  // namespace

bool weightedCentroid(const StarPatch& patch, const Vec2& start, double weight_sigma,
                      int max_iter, Centroid& out, std::string* reason) {
  if (weight_sigma <= 0) return flatCentroid(patch, out, reason);
  const cv::Mat1f& v = patch.values;
  thread_local std::vector<double> gx, gy;
  gx.resize(static_cast<std::size_t>(v.cols));
  gy.resize(static_cast<std::size_t>(v.rows));
  SeparableWeights w{1.0 / (weight_sigma * weight_sigma), gx, gy};
  Vec2 x = start;
  if (!iterateWeighted(patch, max_iter, w, x, reason)) return false;
  const double ox = patch.origin.x, oy = patch.origin.y;
  if (x.x() < ox - 0.5 || x.y() < oy - 0.5 || x.x() > ox + v.cols - 0.5 ||
      x.y() > oy + v.rows - 0.5) {
    if (reason) *reason = "centroid left the window";
    return false;
  }
  return fixedPointCovariance(patch, x, w, out, reason);
}

}  // namespace st::detail

// "gauss": maximum-likelihood fit of the pixel-integrated Gaussian PSF (seed 004 §4.2.2,
// eq. 4.5-4.9: the MLE solves Q_x = Q_y = 0 for that model). Parameters x, y, flux F,
// background B and PSF sigma s; Levenberg-Marquardt on the weighted residuals with the
// variance of each pixel taken from the model (Poisson shot + background + read noise), i.e.
// iteratively reweighted least squares, which is the Gaussian approximation of the ML.
// Covariance: inverse Fisher information (J^T W J)^-1 at the solution, its x-y block.
#include <algorithm>
#include <cmath>
#include <vector>

#include <Eigen/Dense>

#include "sensors/detect/pixel_gaussian.hpp"
#include "sensors/detect/weighted_centroid.hpp"

namespace st {
namespace {

using Vec5 = Eigen::Matrix<double, 5, 1>;
using Mat5 = Eigen::Matrix<double, 5, 5>;

struct Normal {
  Mat5 H = Mat5::Zero();
  Vec5 g = Vec5::Zero();
  double chi2 = 0;
  int n = 0;
};

class GaussFitCentroider final : public Centroider {
 public:
  std::string name() const override { return "gauss"; }

 private:
  // Builds J^T W J, J^T W r and chi2 at p, with weights from the model at `pw`.
  static Normal normal(const StarPatch& P, const Vec5& p, const Vec5& pw, bool need_h) {
    const cv::Mat1f& v = P.values;
    thread_local std::vector<PixelGaussian1d> gx, gy, wx, wy;
    auto fill = [](std::vector<PixelGaussian1d>& out, int n, int o, double c, double s) {
      out.resize(static_cast<std::size_t>(n));
      for (int k = 0; k < n; ++k) out[static_cast<std::size_t>(k)] = pixelGaussian1d(o + k, c, s);
    };
    fill(gx, v.cols, P.origin.x, p[0], p[4]);
    fill(gy, v.rows, P.origin.y, p[1], p[4]);
    const bool same = (pw.array() == p.array()).all();
    if (!same) {
      fill(wx, v.cols, P.origin.x, pw[0], pw[4]);
      fill(wy, v.rows, P.origin.y, pw[1], pw[4]);
    }
    const auto& wgx = same ? gx : wx;
    const auto& wgy = same ? gy : wy;
    Normal N;
    const double F = p[2], B = p[3];
    for (int r = 0; r < v.rows; ++r) {
      const float* row = v[r];
      const PixelGaussian1d& ey = gy[static_cast<std::size_t>(r)];
      const double wfy = wgy[static_cast<std::size_t>(r)].f;
      for (int c = 0; c < v.cols; ++c) {
        if (row[c] >= P.saturation) continue;  // clipped pixels carry no shape information
        const PixelGaussian1d& ex = gx[static_cast<std::size_t>(c)];
        const double w = 1.0 / P.variance(pw[2] * wgx[static_cast<std::size_t>(c)].f * wfy);
        const double res = row[c] - (B + F * ex.f * ey.f);
        N.chi2 += w * res * res;
        ++N.n;
        if (!need_h) continue;
        Vec5 j;
        j << F * ex.df_dx * ey.f, F * ex.f * ey.df_dx, ex.f * ey.f, 1.0,
            F * (ex.df_ds * ey.f + ex.f * ey.df_ds);
        N.H.selfadjointView<Eigen::Lower>().rankUpdate(j, w);
        N.g += w * res * j;
      }
    }
    N.H = N.H.selfadjointView<Eigen::Lower>();
    return N;
  }

  bool doCentroid(const StarPatch& P, Centroid& out, std::string* reason) const override {
    // Start from the plain CoG (robust), flux from its sum.
    Centroid start;
    if (!detail::weightedCentroid(P, P.guess, 0.0, 1, start, reason)) return false;
    Vec5 p;
    p << start.px.x(), start.px.y(), std::max(start.flux, start.peak), P.background,
        std::clamp(P.psf_sigma, 0.4, 10.0);
    double lambda = 1e-3;
    Normal N = normal(P, p, p, true);
    if (N.n < 7) {
      if (reason) *reason = "too few unsaturated pixels to fit";
      return false;
    }
    // Each trial builds its normal equations with the weights of the current estimate, so an
    // accepted trial is reused as the next linearisation (weights lag one step; at the fixed
    // point they are the model's, as ML requires).
    for (int it = 0; it < 20; ++it) {
      Mat5 A = N.H;
      A.diagonal() *= (1.0 + lambda);
      const Vec5 d = A.ldlt().solve(N.g);
      if (!d.allFinite()) break;
      Vec5 q = p + d;
      q[4] = std::clamp(q[4], 0.25, 20.0);
      const Normal T = normal(P, q, p, true);
      if (T.chi2 <= N.chi2 + 1e-12) {
        p = q;
        N = T;
        lambda = std::max(lambda * 0.1, 1e-7);
        if (d.head<2>().norm() < 1e-4 && std::abs(d[4]) < 1e-3) break;
      } else {
        lambda *= 10;
        if (lambda > 1e8) break;
      }
    }
    N = normal(P, p, p, true);  // covariance with the weights at the solution
    const double ox = P.origin.x, oy = P.origin.y;
    if (!p.allFinite() || !(p[2] > 0) || p[0] < ox - 0.5 || p[1] < oy - 0.5 ||
        p[0] > ox + P.values.cols - 0.5 || p[1] > oy + P.values.rows - 0.5 || p[4] >= 20.0) {
      if (reason) *reason = "PSF fit diverged";
      return false;
    }
    const Mat5 C = N.H.inverse();  // Fisher information inverse = Cramer-Rao covariance
    if (!C.allFinite() || !(C(0, 0) > 0) || !(C(1, 1) > 0) || !(C(2, 2) > 0)) {
      if (reason) *reason = "PSF fit singular";
      return false;
    }
    out.px = p.head<2>();
    out.cov_px = C.topLeftCorner<2, 2>();
    out.flux = p[2];
    out.peak = start.peak;
    out.snr = p[2] / std::sqrt(C(2, 2));
    return true;
  }
};

}  // namespace

std::unique_ptr<Centroider> makeGaussFitCentroider() {
  return std::make_unique<GaussFitCentroider>();
}

}  // namespace st

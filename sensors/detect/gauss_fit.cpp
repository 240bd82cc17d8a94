// "gauss": maximum-likelihood fit of the pixel-integrated Gaussian PSF (seed 004 §4.2.2,
// eq. 4.5-4.9: the MLE solves Q_x = Q_y = 0 for that model). Parameters x, y, flux F,
// background B and PSF sigma s; Levenberg-Marquardt on the weighted residuals with the
// variance of each pixel taken from the model (Poisson shot + background + read noise), i.e.
// iteratively reweighted least squares, which is the Gaussian approximation of the ML.
// Covariance: inverse Fisher information (J^T W J)^-1 at the solution, its x-y block.
//
// Speed (this runs once per star per frame, and for every predictive window):
//  - the model is separable, f_ij = fx_i * fy_j: the pixel-integrated Gaussian is evaluated
//    once per pixel EDGE per axis (cols + rows + 2 per evaluation, pixel_gaussian.hpp, from a
//    Hermite table instead of erfc/exp), and every entry of J^T W J is a row factor times a
//    weighted column sum, so the per-pixel work is 15 multiply-adds;
//  - one pass over the pixels per LM trial: the trial's normal equations are built with the
//    trial's own weights (IRLS) and, in the same pass, its chi2 with the stored weights of the
//    current estimate, so that accepting or rejecting it compares like with like;
//  - the start is the background-subtracted centre of gravity, so Gauss-Newton converges in
//    3-5 trials; the loop stops on an accepted step below 1e-3 px (position) and 1e-2 px
//    (sigma), after which the remaining error is ~1e-6 px (quadratic convergence);
//  - the Fisher information of the last accepted trial is the one at the solution: no extra
//    pass for the covariance;
//  - tables and weights live in per-thread buffers: no allocation per star.
#include <algorithm>
#include <cmath>
#include <vector>

#include <Eigen/Dense>

#include "sensors/detect/centroider.hpp"
#include "sensors/detect/pixel_gaussian.hpp"

namespace st {
namespace {

using Vec5 = Eigen::Matrix<double, 5, 1>;
using Mat5 = Eigen::Matrix<double, 5, 5>;

constexpr int kMaxTrials = 20;
// Stop once an accepted step moves the position less than this (Gauss-Newton converges
// quadratically: the remaining error is then ~1e-6 px, far below any Cramer-Rao bound).
constexpr double kStepTolPx = 1e-3;
constexpr double kStepTolSigma = 1e-2;

// Per-column tables of the model at one parameter vector, and the per-pixel weights.
struct Work {
  std::vector<double> fx, dx, sx, fy, dy, sy;      // f, df/dc, df/ds per column / row
  std::vector<double> pdd, pdf, pds, pff, pfs, pss;  // column products for the sums below
  std::vector<double> w_cur, w_trial;              // per-pixel weights (row-major)
  void resize(int cols, int rows) {
    for (auto* v : {&fx, &dx, &sx, &pdd, &pdf, &pds, &pff, &pfs, &pss})
      v->resize(static_cast<std::size_t>(cols));
    for (auto* v : {&fy, &dy, &sy}) v->resize(static_cast<std::size_t>(rows));
    w_cur.resize(static_cast<std::size_t>(cols * rows));
    w_trial.resize(w_cur.size());
  }
};

// Normal equations of the weighted least squares at p with the weights of the model at p
// (IRLS), stored in `w_out`; and the chi2 of the residuals at p with the weights `w_prev`
// (those of the current estimate), so that a trial is judged on a fixed weighted problem.
struct Normal {
  Mat5 H;
  Vec5 g;
  double chi2_self = 0;  // weights at p
  double chi2_prev = 0;  // weights w_prev
};

// With j = (F fy dx, F dy fx, fx fy, 1, F (fy sx + sy fx)) for the pixel in column c, row r,
// every entry of J^T W J is a row factor times a column sum sum_c w_rc * (product of the
// column tables dx, fx, sx): 10 weighted sums and 4 residual sums per row, instead of 15 + 5
// products of Jacobian entries per pixel.
void evaluate(const StarPatch& P, const Vec5& p, Work& W, double* w_out, const double* w_prev,
              Normal& N) {
  const cv::Mat1f& v = P.values;
  const int cols = v.cols, rows = v.rows;
  pixelGaussianRow(cols, P.origin.x, p[0], p[4], W.fx.data(), W.dx.data(), W.sx.data());
  pixelGaussianRow(rows, P.origin.y, p[1], p[4], W.fy.data(), W.dy.data(), W.sy.data());
  const double* fx = W.fx.data();
  const double* dx = W.dx.data();
  const double* sx = W.sx.data();
  for (int c = 0; c < cols; ++c) {
    W.pdd[c] = dx[c] * dx[c];
    W.pdf[c] = dx[c] * fx[c];
    W.pds[c] = dx[c] * sx[c];
    W.pff[c] = fx[c] * fx[c];
    W.pfs[c] = fx[c] * sx[c];
    W.pss[c] = sx[c] * sx[c];
  }
  const double* pdd = W.pdd.data();
  const double* pdf = W.pdf.data();
  const double* pds = W.pds.data();
  const double* pff = W.pff.data();
  const double* pfs = W.pfs.data();
  const double* pss = W.pss.data();
  const double F = p[2], B = p[3];
  const double sb2 = P.sigma_bg * P.sigma_bg, inv_gain = 1.0 / P.gain, sat = P.saturation;
  double h00 = 0, h01 = 0, h02 = 0, h03 = 0, h04 = 0, h11 = 0, h12 = 0, h13 = 0, h14 = 0;
  double h22 = 0, h23 = 0, h24 = 0, h33 = 0, h34 = 0, h44 = 0;
  double g0 = 0, g1 = 0, g2 = 0, g3 = 0, g4 = 0, chi2 = 0, chi2w = 0;
  for (int r = 0; r < rows; ++r) {
    const float* row = v[r];
    double* wr_out = w_out + static_cast<std::ptrdiff_t>(r) * cols;
    const double* wr_prev = w_prev ? w_prev + static_cast<std::ptrdiff_t>(r) * cols : nullptr;
    const double fy = W.fy[static_cast<std::size_t>(r)];
    const double Ffy = F * fy, Fdy = F * W.dy[static_cast<std::size_t>(r)];
    const double Fsy = F * W.sy[static_cast<std::size_t>(r)];
    double add = 0, adf = 0, ads = 0, ad = 0, aff = 0, afs = 0, af = 0, ass = 0, as = 0, a1 = 0;
    double bd = 0, bf = 0, bs = 0, b1 = 0, cc = 0, cw = 0;
    for (int c = 0; c < cols; ++c) {
      const double val = row[c];
      const double m = Ffy * fx[c];
      // Clipped pixels carry no shape information: weight 0.
      const double w = val < sat ? 1.0 / (sb2 + (m > 0 ? m * inv_gain : 0.0)) : 0.0;
      wr_out[c] = w;
      const double res = val - B - m;
      const double wres = w * res;
      cc += wres * res;
      if (wr_prev) cw += wr_prev[c] * res * res;
      bd += wres * dx[c];
      bf += wres * fx[c];
      bs += wres * sx[c];
      b1 += wres;
      add += w * pdd[c];
      adf += w * pdf[c];
      ads += w * pds[c];
      ad += w * dx[c];
      aff += w * pff[c];
      afs += w * pfs[c];
      af += w * fx[c];
      ass += w * pss[c];
      as += w * sx[c];
      a1 += w;
    }
    // j0 = Ffy dx, j1 = Fdy fx, j2 = fy fx, j3 = 1, j4 = Ffy sx + Fsy fx.
    const double a4f = Ffy * afs + Fsy * aff;  // sum w j4 fx
    h00 += Ffy * Ffy * add;
    h01 += Ffy * Fdy * adf;
    h02 += Ffy * fy * adf;
    h03 += Ffy * ad;
    h04 += Ffy * (Ffy * ads + Fsy * adf);
    h11 += Fdy * Fdy * aff;
    h12 += Fdy * fy * aff;
    h13 += Fdy * af;
    h14 += Fdy * a4f;
    h22 += fy * fy * aff;
    h23 += fy * af;
    h24 += fy * a4f;
    h33 += a1;
    h34 += Ffy * as + Fsy * af;
    h44 += Ffy * Ffy * ass + 2 * Ffy * Fsy * afs + Fsy * Fsy * aff;
    g0 += Ffy * bd;
    g1 += Fdy * bf;
    g2 += fy * bf;
    g3 += b1;
    g4 += Ffy * bs + Fsy * bf;
    chi2 += cc;
    chi2w += cw;
  }
  N.H << h00, h01, h02, h03, h04,  //
      h01, h11, h12, h13, h14,     //
      h02, h12, h22, h23, h24,     //
      h03, h13, h23, h33, h34,     //
      h04, h14, h24, h34, h44;
  N.g << g0, g1, g2, g3, g4;
  N.chi2_self = chi2;
  N.chi2_prev = w_prev ? chi2w : chi2;
}

class GaussFitCentroider final : public Centroider {
 public:
  std::string name() const override { return "gauss"; }

 private:
  bool doCentroid(const StarPatch& P, Centroid& out, std::string* reason) const override {
    const cv::Mat1f& v = P.values;
    const double ox = P.origin.x, oy = P.origin.y;
    // Start: the background-subtracted centre of gravity (seed 004 eq. 4.1), flux its sum.
    double sw = 0, sx = 0, sy = 0, peak = -1e300;
    int unsaturated = 0;
    for (int r = 0; r < v.rows; ++r) {
      const float* row = v[r];
      double rs = 0, rx = 0;
      for (int c = 0; c < v.cols; ++c) {
        const double s = row[c] - P.background;
        rs += s;
        rx += s * c;
        peak = std::max(peak, s);
        unsaturated += row[c] < P.saturation;
      }
      sw += rs;
      sx += rx;
      sy += rs * r;
    }
    if (!(sw > 0)) {
      if (reason) *reason = "no flux above background";
      return false;
    }
    Vec5 p;
    p << ox + sx / sw, oy + sy / sw, std::max(sw, peak), P.background,
        std::clamp(P.psf_sigma, 0.4, 10.0);
    if (p[0] < ox - 0.5 || p[1] < oy - 0.5 || p[0] > ox + v.cols - 0.5 ||
        p[1] > oy + v.rows - 0.5) {
      if (reason) *reason = "centroid left the window";
      return false;
    }
    if (unsaturated < 7) {
      if (reason) *reason = "too few unsaturated pixels to fit";
      return false;
    }
    thread_local Work work;
    work.resize(v.cols, v.rows);
    double* w_cur = work.w_cur.data();
    double* w_trial = work.w_trial.data();
    Normal N, T;
    evaluate(P, p, work, w_cur, nullptr, N);
    double lambda = 1e-3;
    for (int it = 0; it < kMaxTrials; ++it) {
      Mat5 A = N.H;
      A.diagonal() *= (1.0 + lambda);
      const Vec5 d = A.ldlt().solve(N.g);
      if (!d.allFinite()) break;
      Vec5 q = p + d;
      q[4] = std::clamp(q[4], 0.25, 20.0);
      evaluate(P, q, work, w_trial, w_cur, T);
      // Accept when the chi2 with the current weights does not grow (a fixed weighted
      // least-squares problem on both sides of the comparison).
      if (T.chi2_prev <= N.chi2_self + 1e-12) {
        p = q;
        N = T;
        std::swap(w_cur, w_trial);
        lambda = std::max(lambda * 0.1, 1e-7);
        if (d.head<2>().norm() < kStepTolPx && std::abs(d[4]) < kStepTolSigma) break;
      } else {
        lambda *= 10;
        if (lambda > 1e8) break;
      }
    }
    if (!p.allFinite() || !(p[2] > 0) || p[0] < ox - 0.5 || p[1] < oy - 0.5 ||
        p[0] > ox + v.cols - 0.5 || p[1] > oy + v.rows - 0.5 || p[4] >= 20.0) {
      if (reason) *reason = "PSF fit diverged";
      return false;
    }
    // N holds the normal equations at p with the weights at p: the Fisher information.
    const Mat5 C = N.H.inverse();  // Fisher information inverse = Cramer-Rao covariance
    if (!C.allFinite() || !(C(0, 0) > 0) || !(C(1, 1) > 0) || !(C(2, 2) > 0)) {
      if (reason) *reason = "PSF fit singular";
      return false;
    }
    out.px = p.head<2>();
    out.cov_px = C.topLeftCorner<2, 2>();
    out.flux = p[2];
    out.peak = peak;
    out.snr = p[2] / std::sqrt(C(2, 2));
    return true;
  }
};

}  // namespace

std::unique_ptr<Centroider> makeGaussFitCentroider() {
  return std::make_unique<GaussFitCentroider>();
}

}  // namespace st

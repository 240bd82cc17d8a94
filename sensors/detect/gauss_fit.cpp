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
//    weighted column sum, so the per-pixel work is 15 multiply-adds, two pixels at a time
//    (SSE2, the x86-64 baseline; a scalar loop elsewhere);
//  - one pass over the pixels per LM trial: the trial's normal equations are built with the
//    trial's own weights (IRLS) and, in the same pass, its chi2 with the stored weights of the
//    current estimate, so that accepting or rejecting it compares like with like;
//  - the start is the background-subtracted centre of gravity, so Gauss-Newton converges in
//    a few trials; once the proposed step is below 1e-3 px (position) and 1e-2 px (sigma) it
//    is taken without another pass (the remaining error is then ~1e-6 px, quadratic
//    convergence), and the Fisher information of the last pass, 1e-3 px away, gives the
//    covariance;
//  - 5x5 Cholesky by hand (no dynamic-size paths); tables, weights and the pixel copy live in
//    per-thread buffers: no allocation per star.
#include <algorithm>
#include <cmath>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "sensors/detect/centroider.hpp"
#include "sensors/detect/pixel_gaussian.hpp"

namespace st {
namespace {

constexpr int kMaxTrials = 20;
// Stop once a proposed step is negligible, and take it without another pass: either it moves
// the position less than kStepTolPx (and sigma less than kStepTolSigma), or its length in
// the metric of the Fisher information (d^T H d = g^T d, the predicted chi2 decrease) is
// below kStepTolChi2, i.e. the step is under 0.1 of the 1-sigma error ellipsoid. The error
// left is the next step, a fraction (the convergence rate, 0.1-0.3 here) of that: it adds
// < 0.1% to the variance.
constexpr double kStepTolPx = 1e-3;
constexpr double kStepTolSigma = 1e-2;
constexpr double kStepTolChi2 = 0.1 * 0.1;

// 5x5 symmetric matrices and vectors as plain arrays (parameters x, y, F, B, s).
using M5 = double[5][5];
using V5 = double[5];

// Cholesky factor L (lower) of a symmetric positive definite A; false if not positive definite.
bool cholesky5(const M5& A, M5& L) {
  for (int j = 0; j < 5; ++j) {
    double d = A[j][j];
    for (int k = 0; k < j; ++k) d -= L[j][k] * L[j][k];
    if (!(d > 0)) return false;
    L[j][j] = std::sqrt(d);
    const double inv = 1.0 / L[j][j];
    for (int i = j + 1; i < 5; ++i) {
      double s = A[i][j];
      for (int k = 0; k < j; ++k) s -= L[i][k] * L[j][k];
      L[i][j] = s * inv;
    }
  }
  return true;
}

// x = (L L^T)^-1 b
void cholSolve5(const M5& L, const V5& b, V5& x) {
  V5 y;
  for (int i = 0; i < 5; ++i) {
    double s = b[i];
    for (int k = 0; k < i; ++k) s -= L[i][k] * y[k];
    y[i] = s / L[i][i];
  }
  for (int i = 4; i >= 0; --i) {
    double s = y[i];
    for (int k = i + 1; k < 5; ++k) s -= L[k][i] * x[k];
    x[i] = s / L[i][i];
  }
}

// Per-fit buffers. The pixels are stored two rows at a time, interleaved, so that one SSE2
// register holds the same column of two rows: (r, c) of row pair k = r / 2 and lane r % 2 is
// at (k * cols + c) * 2 + lane. Column tables are stored duplicated (both lanes the same),
// row tables per lane. An odd last row gets a pad row with no usable pixel.
struct Work {
  int cols = 0, rows = 0, pairs = 0;
  std::vector<double> val, use;                      // pixel value; 1 if usable else 0
  std::vector<double> w_cur, w_trial;                // per-pixel weights
  std::vector<double> fx, dx, sx, fy, dy, sy;        // f, df/dc, df/ds per column / row
  std::vector<double> pdd, pdf, pds, pff, pfs, pss;  // column products for the sums below
  void reset(const StarPatch& P) {
    cols = P.values.cols;
    rows = P.values.rows;
    pairs = (rows + 1) / 2;
    const std::size_t n = static_cast<std::size_t>(pairs) * static_cast<std::size_t>(cols) * 2;
    for (auto* v : {&val, &use, &w_cur, &w_trial}) v->resize(n);
    for (auto* v : {&fx, &dx, &sx, &pdd, &pdf, &pds, &pff, &pfs, &pss})
      v->resize(static_cast<std::size_t>(cols) * 2);
    for (auto* v : {&fy, &dy, &sy}) v->assign(static_cast<std::size_t>(pairs) * 2, 0.0);
    for (int r = 0; r < pairs * 2; ++r) {
      const float* in = r < rows ? P.values[r] : nullptr;
      for (int c = 0; c < cols; ++c) {
        const std::size_t i = static_cast<std::size_t>(((r / 2) * cols + c) * 2 + (r & 1));
        val[i] = in ? in[c] : 0.0;
        use[i] = in && in[c] < P.saturation ? 1.0 : 0.0;  // clipped: no shape information
        w_trial[i] = 0;  // "previous weights" of the first evaluation
      }
    }
  }
};

// Per-lane (row) sums over the columns, for the pixel at column c with weight w and residual
// res:  a_k = sum_c w * colprod_k(c)  (dx^2, dx fx, dx sx, dx, fx^2, fx sx, fx, sx^2, sx, 1),
// b_k = sum_c w res (dx, fx, sx, 1),  cc = sum w res^2,  cw = sum w_prev res^2.
enum Sum { kAdd, kAdf, kAds, kAd, kAff, kAfs, kAf, kAss, kAs, kA1, kBd, kBf, kBs, kB1, kCc, kCw,
           kNumSums };

#if defined(__SSE2__)
// One row pair, two rows per register (lanes). Buffers come from operator new (16-byte
// aligned) and every index is even: aligned loads.
void rowPairSums(const Work& W, int k, const __m128d vFfy, double B, double sb2,
                 double inv_gain, double* w_out, const double* w_prev, __m128d* s) {
  const std::size_t o = static_cast<std::size_t>(k * W.cols) * 2;
  const double* val = W.val.data() + o;
  const double* use = W.use.data() + o;
  const double* wp = w_prev + o;
  double* wo = w_out + o;
  const double *fx = W.fx.data(), *dx = W.dx.data(), *sx = W.sx.data();
  const __m128d vB = _mm_set1_pd(B), vsb2 = _mm_set1_pd(sb2), vig = _mm_set1_pd(inv_gain);
  const __m128d zero = _mm_setzero_pd();
  __m128d cc = zero, cw = zero, bd = zero, bf = zero, bs = zero, b1 = zero;
  const int n = 2 * W.cols;
  for (int c = 0; c < n; c += 2) {
    const __m128d f = _mm_load_pd(fx + c);
    const __m128d m = _mm_mul_pd(vFfy, f);
    const __m128d var = _mm_add_pd(vsb2, _mm_mul_pd(_mm_max_pd(m, zero), vig));
    const __m128d w = _mm_div_pd(_mm_load_pd(use + c), var);
    _mm_store_pd(wo + c, w);
    const __m128d res = _mm_sub_pd(_mm_sub_pd(_mm_load_pd(val + c), vB), m);
    const __m128d wr = _mm_mul_pd(w, res);
    cc = _mm_add_pd(cc, _mm_mul_pd(wr, res));
    cw = _mm_add_pd(cw, _mm_mul_pd(_mm_load_pd(wp + c), _mm_mul_pd(res, res)));
    bd = _mm_add_pd(bd, _mm_mul_pd(wr, _mm_load_pd(dx + c)));
    bf = _mm_add_pd(bf, _mm_mul_pd(wr, f));
    bs = _mm_add_pd(bs, _mm_mul_pd(wr, _mm_load_pd(sx + c)));
    b1 = _mm_add_pd(b1, wr);
  }
  __m128d add = zero, adf = zero, ads = zero, ad = zero, aff = zero, afs = zero, af = zero,
          ass = zero, as = zero, a1 = zero;
  const double *pdd = W.pdd.data(), *pdf = W.pdf.data(), *pds = W.pds.data();
  const double *pff = W.pff.data(), *pfs = W.pfs.data(), *pss = W.pss.data();
  for (int c = 0; c < n; c += 2) {
    const __m128d w = _mm_load_pd(wo + c);
    add = _mm_add_pd(add, _mm_mul_pd(w, _mm_load_pd(pdd + c)));
    adf = _mm_add_pd(adf, _mm_mul_pd(w, _mm_load_pd(pdf + c)));
    ads = _mm_add_pd(ads, _mm_mul_pd(w, _mm_load_pd(pds + c)));
    ad = _mm_add_pd(ad, _mm_mul_pd(w, _mm_load_pd(dx + c)));
    aff = _mm_add_pd(aff, _mm_mul_pd(w, _mm_load_pd(pff + c)));
    afs = _mm_add_pd(afs, _mm_mul_pd(w, _mm_load_pd(pfs + c)));
    af = _mm_add_pd(af, _mm_mul_pd(w, _mm_load_pd(fx + c)));
    ass = _mm_add_pd(ass, _mm_mul_pd(w, _mm_load_pd(pss + c)));
    as = _mm_add_pd(as, _mm_mul_pd(w, _mm_load_pd(sx + c)));
    a1 = _mm_add_pd(a1, w);
  }
  s[kAdd] = add, s[kAdf] = adf, s[kAds] = ads, s[kAd] = ad, s[kAff] = aff, s[kAfs] = afs;
  s[kAf] = af, s[kAss] = ass, s[kAs] = as, s[kA1] = a1, s[kBd] = bd, s[kBf] = bf;
  s[kBs] = bs, s[kB1] = b1, s[kCc] = cc, s[kCw] = cw;
}
#endif

// Normal equations of the weighted least squares at p with the weights of the model at p
// (IRLS), the weights stored in `w_out`; and the chi2 of the residuals at p with the weights
// `w_prev` (those of the current estimate), so that a trial is judged on a fixed weighted
// problem.
struct Normal {
  M5 H;
  V5 g;
  double chi2_self = 0;  // weights at p
  double chi2_prev = 0;  // weights w_prev
};

// Totals accumulated over the rows: the 15 entries of J^T W J, J^T W r and the two chi2.
enum Total { kH00, kH01, kH02, kH03, kH04, kH11, kH12, kH13, kH14, kH22, kH23, kH24, kH33,
             kH34, kH44, kG0, kG1, kG2, kG3, kG4, kChi2, kChi2w, kNumTotals };

// Adds one row's (or, lane-wise, one row pair's) sums times its row factors to the totals.
// With j = (F fy dx, F dy fx, fx fy, 1, F (fy sx + sy fx)) for the pixel in column c, row r,
// every entry of J^T W J is a row factor times a column sum sum_c w_rc * (product of the
// column tables dx, fx, sx): 10 weighted sums and 4 residual sums per row, instead of 15 + 5
// products of Jacobian entries per pixel. T is double or __m128d.
template <typename T>
void addRow(const T* s, T fy, T Ffy, T Fdy, T Fsy, T* t) {
  const T a4f = Ffy * s[kAfs] + Fsy * s[kAff];  // sum w j4 fx
  t[kH00] += Ffy * Ffy * s[kAdd];
  t[kH01] += Ffy * Fdy * s[kAdf];
  t[kH02] += Ffy * fy * s[kAdf];
  t[kH03] += Ffy * s[kAd];
  t[kH04] += Ffy * (Ffy * s[kAds] + Fsy * s[kAdf]);
  t[kH11] += Fdy * Fdy * s[kAff];
  t[kH12] += Fdy * fy * s[kAff];
  t[kH13] += Fdy * s[kAf];
  t[kH14] += Fdy * a4f;
  t[kH22] += fy * fy * s[kAff];
  t[kH23] += fy * s[kAf];
  t[kH24] += fy * a4f;
  t[kH33] += s[kA1];
  t[kH34] += Ffy * s[kAs] + Fsy * s[kAf];
  t[kH44] += Ffy * (Ffy * s[kAss] + Fsy * s[kAfs]) + Fsy * (Ffy * s[kAfs] + Fsy * s[kAff]);
  t[kG0] += Ffy * s[kBd];
  t[kG1] += Fdy * s[kBf];
  t[kG2] += fy * s[kBf];
  t[kG3] += s[kB1];
  t[kG4] += Ffy * s[kBs] + Fsy * s[kBf];
  t[kChi2] += s[kCc];
  t[kChi2w] += s[kCw];
}

void evaluate(const StarPatch& P, const V5& p, Work& W, double* w_out, const double* w_prev,
              Normal& N) {
  // Column tables, duplicated for the two lanes; row tables (pad row stays 0).
  thread_local std::vector<double> cx, cdx, csx;
  cx.resize(static_cast<std::size_t>(W.cols));
  cdx.resize(cx.size());
  csx.resize(cx.size());
  pixelGaussianRow(W.cols, P.origin.x, p[0], p[4], cx.data(), cdx.data(), csx.data());
  pixelGaussianRow(W.rows, P.origin.y, p[1], p[4], W.fy.data(), W.dy.data(), W.sy.data());
  for (int c = 0; c < W.cols; ++c) {
    const std::size_t i = static_cast<std::size_t>(c);
    const double f = cx[i], d = cdx[i], s = csx[i];
    const double col[9] = {f, d, s, d * d, d * f, d * s, f * f, f * s, s * s};
    std::vector<double>* dst[9] = {&W.fx, &W.dx, &W.sx, &W.pdd, &W.pdf, &W.pds, &W.pff, &W.pfs,
                                   &W.pss};
    for (int k = 0; k < 9; ++k) (*dst[k])[2 * i] = (*dst[k])[2 * i + 1] = col[k];
  }
  const double F = p[2], B = p[3];
  const double sb2 = P.sigma_bg * P.sigma_bg, inv_gain = 1.0 / P.gain;
  double tot[kNumTotals] = {};
#if defined(__SSE2__)
  __m128d vt[kNumTotals];
  for (auto& x : vt) x = _mm_setzero_pd();
  const __m128d vF = _mm_set1_pd(F);
  for (int k = 0; k < W.pairs; ++k) {
    const __m128d fy = _mm_loadu_pd(W.fy.data() + 2 * k);
    const __m128d Ffy = _mm_mul_pd(vF, fy);
    const __m128d Fdy = _mm_mul_pd(vF, _mm_loadu_pd(W.dy.data() + 2 * k));
    const __m128d Fsy = _mm_mul_pd(vF, _mm_loadu_pd(W.sy.data() + 2 * k));
    __m128d s[kNumSums];
    rowPairSums(W, k, Ffy, B, sb2, inv_gain, w_out, w_prev, s);
    addRow(s, fy, Ffy, Fdy, Fsy, vt);
  }
  for (int i = 0; i < kNumTotals; ++i)
    tot[i] = _mm_cvtsd_f64(_mm_add_sd(vt[i], _mm_unpackhi_pd(vt[i], vt[i])));
#else
  for (int r = 0; r < W.rows; ++r) {
    const int lane = r & 1;
    const std::size_t o = static_cast<std::size_t>((r / 2) * W.cols) * 2 + lane;
    const double fy = W.fy[static_cast<std::size_t>(r)], Ffy = F * fy;
    double s[kNumSums] = {};
    for (int c = 0; c < W.cols; ++c) {
      const std::size_t i = o + 2 * static_cast<std::size_t>(c), j = 2 * static_cast<std::size_t>(c);
      const double m = Ffy * W.fx[j];
      const double w = W.use[i] / (sb2 + (m > 0 ? m * inv_gain : 0.0));
      w_out[i] = w;
      const double res = W.val[i] - B - m, wr = w * res;
      const double cols[kA1 + 1] = {W.pdd[j], W.pdf[j], W.pds[j], W.dx[j], W.pff[j],
                                    W.pfs[j], W.fx[j],  W.pss[j], W.sx[j], 1.0};
      for (int k = 0; k <= kA1; ++k) s[k] += w * cols[k];
      s[kBd] += wr * W.dx[j];
      s[kBf] += wr * W.fx[j];
      s[kBs] += wr * W.sx[j];
      s[kB1] += wr;
      s[kCc] += wr * res;
      s[kCw] += w_prev[i] * res * res;
    }
    addRow(s, fy, Ffy, F * W.dy[static_cast<std::size_t>(r)],
           F * W.sy[static_cast<std::size_t>(r)], tot);
  }
#endif
  const double H[5][5] = {{tot[kH00], tot[kH01], tot[kH02], tot[kH03], tot[kH04]},
                          {tot[kH01], tot[kH11], tot[kH12], tot[kH13], tot[kH14]},
                          {tot[kH02], tot[kH12], tot[kH22], tot[kH23], tot[kH24]},
                          {tot[kH03], tot[kH13], tot[kH23], tot[kH33], tot[kH34]},
                          {tot[kH04], tot[kH14], tot[kH24], tot[kH34], tot[kH44]}};
  std::copy(&H[0][0], &H[0][0] + 25, &N.H[0][0]);
  for (int k = 0; k < 5; ++k) N.g[k] = tot[kG0 + k];
  N.chi2_self = tot[kChi2];
  N.chi2_prev = tot[kChi2w];
}

// Flux and background at the starting position and sigma by unweighted linear least squares
// (v = B + F f): the centre of gravity's flux inherits the whole error of the local background
// times the window area, which would cost Gauss-Newton an extra step or two.
void linearStart(const StarPatch& P, const Work& W, V5& p) {
  thread_local std::vector<double> fx, fy, tmp1, tmp2;
  fx.resize(static_cast<std::size_t>(W.cols));
  fy.resize(static_cast<std::size_t>(W.rows));
  tmp1.resize(std::max(fx.size(), fy.size()));
  tmp2.resize(tmp1.size());
  pixelGaussianRow(W.cols, P.origin.x, p[0], p[4], fx.data(), tmp1.data(), tmp2.data());
  pixelGaussianRow(W.rows, P.origin.y, p[1], p[4], fy.data(), tmp1.data(), tmp2.data());
  double n = 0, sf = 0, sff = 0, sv = 0, svf = 0;
  for (int r = 0; r < W.rows; ++r) {
    const float* row = P.values[r];
    const double y = fy[static_cast<std::size_t>(r)];
    for (int c = 0; c < W.cols; ++c) {
      if (!(row[c] < P.saturation)) continue;
      const double f = y * fx[static_cast<std::size_t>(c)];
      n += 1;
      sf += f;
      sff += f * f;
      sv += row[c];
      svf += row[c] * f;
    }
  }
  const double det = sff * n - sf * sf;
  if (!(det > 1e-12 * sff * n)) return;
  const double F = (n * svf - sf * sv) / det, B = (sff * sv - sf * svf) / det;
  if (F > 0 && std::isfinite(F) && std::isfinite(B)) {
    p[2] = F;
    p[3] = B;
  }
}

bool finite5(const V5& v) {
  for (double x : v)
    if (!std::isfinite(x)) return false;
  return true;
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
    V5 p = {ox + sx / sw, oy + sy / sw, std::max(sw, peak), P.background,
            std::clamp(P.psf_sigma, 0.4, 10.0)};
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
    work.reset(P);
    linearStart(P, work, p);
    double* w_cur = work.w_cur.data();
    double* w_trial = work.w_trial.data();
    Normal N, T;
    evaluate(P, p, work, w_cur, w_trial /* zeros: no previous weights */, N);
    double lambda = 1e-3;
    for (int it = 0; it < kMaxTrials; ++it) {
      M5 A, L;
      std::copy(&N.H[0][0], &N.H[0][0] + 25, &A[0][0]);
      for (int k = 0; k < 5; ++k) A[k][k] *= 1.0 + lambda;
      V5 d;
      if (!cholesky5(A, L)) {
        lambda *= 10;
        if (lambda > 1e8) break;
        continue;
      }
      cholSolve5(L, N.g, d);
      if (!finite5(d)) break;
      V5 q;
      for (int k = 0; k < 5; ++k) q[k] = p[k] + d[k];
      q[4] = std::clamp(q[4], 0.25, 20.0);
      double gd = 0;
      for (int k = 0; k < 5; ++k) gd += N.g[k] * d[k];
      if ((d[0] * d[0] + d[1] * d[1] < kStepTolPx * kStepTolPx &&
           std::abs(d[4]) < kStepTolSigma) ||
          gd < kStepTolChi2) {
        std::copy(q, q + 5, p);  // converged: the last step is too small to need checking
        break;
      }
      evaluate(P, q, work, w_trial, w_cur, T);
      // Accept when the chi2 with the current weights does not grow (a fixed weighted
      // least-squares problem on both sides of the comparison).
      if (T.chi2_prev <= N.chi2_self + 1e-12) {
        std::copy(q, q + 5, p);
        N = T;
        std::swap(w_cur, w_trial);
        lambda = std::max(lambda * 0.1, 1e-7);
      } else {
        lambda *= 10;
        if (lambda > 1e8) break;
      }
    }
    if (!finite5(p) || !(p[2] > 0) || p[0] < ox - 0.5 || p[1] < oy - 0.5 ||
        p[0] > ox + v.cols - 0.5 || p[1] > oy + v.rows - 0.5 || p[4] >= 20.0) {
      if (reason) *reason = "PSF fit diverged";
      return false;
    }
    // Covariance: the inverse of the Fisher information J^T W J (Cramer-Rao), columns x, y, F.
    M5 L;
    V5 cx, cy, cf;
    const V5 ex = {1, 0, 0, 0, 0}, ey = {0, 1, 0, 0, 0}, ef = {0, 0, 1, 0, 0};
    if (!cholesky5(N.H, L)) {
      if (reason) *reason = "PSF fit singular";
      return false;
    }
    cholSolve5(L, ex, cx);
    cholSolve5(L, ey, cy);
    cholSolve5(L, ef, cf);
    if (!finite5(cx) || !finite5(cy) || !finite5(cf) || !(cx[0] > 0) || !(cy[1] > 0) ||
        !(cf[2] > 0)) {
      if (reason) *reason = "PSF fit singular";
      return false;
    }
    out.px = Vec2(p[0], p[1]);
    out.cov_px << cx[0], 0.5 * (cx[1] + cy[0]), 0.5 * (cx[1] + cy[0]), cy[1];
    out.flux = p[2];
    out.peak = peak;
    out.snr = p[2] / std::sqrt(cf[2]);
    return true;
  }
};

}  // namespace

std::unique_ptr<Centroider> makeGaussFitCentroider() {
  return std::make_unique<GaussFitCentroider>();
}

}  // namespace st

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

#if defined(__SSE2__) && !defined(ST_DETECT_NO_SIMD)
#include <emmintrin.h>
#endif
#if defined(__GNUC__) && defined(__x86_64__) && !defined(ST_DETECT_NO_AVX2)
#include <immintrin.h>
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
constexpr double kMaxRate2 = 0.25;  // contraction r < 0.5 per step before r is trusted
// A single-pixel spike more than 8 sigma above the fitted model is not the star's: Gaussian
// noise never gets there (1e-15 per pixel), and what the round model misses of a bright
// smeared star reaches 6-7 sigma at the ends of the smear (measured), spread over neighbours.
constexpr double kOutlierSigma = 8.0;
constexpr int kMaxOutliers = 2;

// 5x5 symmetric matrices and vectors as plain arrays (parameters x, y, F, B, s).
using M5 = double[5][5];
using V5 = double[5];

// A = L D L^T (L unit lower triangular) of a symmetric positive definite A, with 1/D: no
// square roots and one division per column (this runs several times per star, a dependent
// chain where each sqrt or division costs its full latency); false if A is not positive
// definite.
struct Ldl5 {
  M5 L;
  V5 d, inv_d;
};

bool factorLdl5(const M5& A, Ldl5& F) {
  V5 ld;  // L[j][k] * D[k] of the current row j
  for (int j = 0; j < 5; ++j) {
    double d = A[j][j];
    for (int k = 0; k < j; ++k) {
      ld[k] = F.L[j][k] * F.d[k];
      d -= F.L[j][k] * ld[k];
    }
    if (!(d > 0)) return false;
    const double inv = 1.0 / d;
    F.d[j] = d;
    F.inv_d[j] = inv;
    for (int i = j + 1; i < 5; ++i) {
      double s = A[i][j];
      for (int k = 0; k < j; ++k) s -= F.L[i][k] * ld[k];
      F.L[i][j] = s * inv;
    }
  }
  return true;
}

// x = (L D L^T)^-1 b
void ldlSolve5(const Ldl5& F, const V5& b, V5& x) {
  V5 y;
  for (int i = 0; i < 5; ++i) {
    double s = b[i];
    for (int k = 0; k < i; ++k) s -= F.L[i][k] * y[k];
    y[i] = s;
  }
  for (int i = 4; i >= 0; --i) {
    double s = y[i] * F.inv_d[i];
    for (int k = i + 1; k < 5; ++k) s -= F.L[k][i] * x[k];
    x[i] = s;
  }
}

// Per-fit buffers. The pixels are stored four rows at a time, interleaved, so that one
// vector register holds the same column of 2 (SSE2) or 4 (AVX2) consecutive rows: pixel
// (r, c) is at ((r / 4) * cols + c) * 4 + r % 4. Rows are padded to a multiple of 4 with
// unusable pixels. Column tables are plain, row tables padded with zeros.
constexpr int kLanes = 4;

struct Work {
  int cols = 0, rows = 0, quads = 0;
  std::vector<double> val, use;                      // pixel value; 1 if usable else 0
  std::vector<double> w_cur, w_trial;                // per-pixel weights
  std::vector<double> fx, dx, sx, fy, dy, sy;        // f, df/dc, df/ds per column / row
  std::vector<double> pdd, pdf, pds, pff, pfs, pss;  // column products for the sums below
  double usable() const {  // pixels in the fit
    double n = 0;
    for (double u : use) n += u;
    return n;
  }
  // Sums of the background-subtracted pixels for the start, taken while the pixels are
  // copied (one pass).
  struct Sums {
    double sw = 0, sx = 0, sy = 0, peak = -1e300;
    int unsaturated = 0;
  };
  Sums reset(const StarPatch& P) {
    cols = P.values.cols;
    rows = P.values.rows;
    quads = (rows + kLanes - 1) / kLanes;
    const std::size_t nr = static_cast<std::size_t>(quads) * kLanes;
    const std::size_t n = nr * static_cast<std::size_t>(cols);
    // The weights need no clearing: every evaluation writes its own, and the "previous
    // weights" the first one reads only enter a chi2 nobody uses.
    for (auto* v : {&val, &use, &w_cur, &w_trial}) v->resize(n);
    for (auto* v : {&fx, &dx, &sx, &pdd, &pdf, &pds, &pff, &pfs, &pss})
      v->resize(static_cast<std::size_t>(cols));
    for (auto* v : {&fy, &dy, &sy}) v->assign(nr, 0.0);
    Sums S;
    for (int r = 0; r < static_cast<int>(nr); ++r) {
      double* pv = val.data() + static_cast<std::size_t>((r / kLanes) * cols * kLanes + r % kLanes);
      double* pu = use.data() + (pv - val.data());
      if (r >= rows) {  // padding: unusable
        for (int c = 0; c < cols; ++c, pv += kLanes, pu += kLanes) *pv = *pu = 0.0;
        continue;
      }
      const float* in = P.values[r];
      double rs = 0, rx = 0;
      for (int c = 0; c < cols; ++c, pv += kLanes, pu += kLanes) {
        const bool ok = in[c] < P.saturation;  // clipped: no shape information
        *pv = in[c];
        *pu = ok ? 1.0 : 0.0;
        S.unsaturated += ok;
        const double s = in[c] - P.background;
        rs += s;
        rx += s * c;
        S.peak = std::max(S.peak, s);
      }
      S.sw += rs;
      S.sx += rx;
      S.sy += rs * r;
    }
    return S;
  }
};

// Per-row sums over the columns, for the pixel at column c with weight w and residual res:
//   a_k = sum_c w * colprod_k(c)  (dx^2, dx fx, dx sx, dx, fx^2, fx sx, fx, sx^2, sx, 1),
//   b_k = sum_c w res (dx, fx, sx, 1),  cc = sum w res^2,  cw = sum w_prev res^2.
enum Sum { kAdd, kAdf, kAds, kAd, kAff, kAfs, kAf, kAss, kAs, kA1, kBd, kBf, kBs, kB1, kCc, kCw,
           kNumSums };

// Totals accumulated over the rows: the 15 entries of J^T W J, J^T W r and the two chi2.
enum Total { kH00, kH01, kH02, kH03, kH04, kH11, kH12, kH13, kH14, kH22, kH23, kH24, kH33,
             kH34, kH44, kG0, kG1, kG2, kG3, kG4, kChi2, kChi2w, kNumTotals };

// Adds one row's sums (or, lane-wise, one register of rows) times its row factors to the
// totals. With j = (F fy dx, F dy fx, fx fy, 1, F (fy sx + sy fx)) for the pixel in column c,
// row r, every entry of J^T W J is a row factor times a column sum sum_c w_rc * (product of
// the column tables dx, fx, sx): 10 weighted sums and 4 residual sums per row, instead of
// 15 + 5 products of Jacobian entries per pixel. T is double, __m128d or __m256d.
#define ST_GAUSS_ADD_ROW(T, s, fy, Ffy, Fdy, Fsy, t)                                        \
  do {                                                                                      \
    const T a4f = Ffy * s[kAfs] + Fsy * s[kAff]; /* sum w j4 fx */                          \
    t[kH00] += Ffy * Ffy * s[kAdd];                                                         \
    t[kH01] += Ffy * Fdy * s[kAdf];                                                         \
    t[kH02] += Ffy * fy * s[kAdf];                                                          \
    t[kH03] += Ffy * s[kAd];                                                                \
    t[kH04] += Ffy * (Ffy * s[kAds] + Fsy * s[kAdf]);                                       \
    t[kH11] += Fdy * Fdy * s[kAff];                                                         \
    t[kH12] += Fdy * fy * s[kAff];                                                          \
    t[kH13] += Fdy * s[kAf];                                                                \
    t[kH14] += Fdy * a4f;                                                                   \
    t[kH22] += fy * fy * s[kAff];                                                           \
    t[kH23] += fy * s[kAf];                                                                 \
    t[kH24] += fy * a4f;                                                                    \
    t[kH33] += s[kA1];                                                                      \
    t[kH34] += Ffy * s[kAs] + Fsy * s[kAf];                                                 \
    t[kH44] += Ffy * (Ffy * s[kAss] + Fsy * s[kAfs]) + Fsy * a4f;                           \
    t[kG0] += Ffy * s[kBd];                                                                 \
    t[kG1] += Fdy * s[kBf];                                                                 \
    t[kG2] += fy * s[kBf];                                                                  \
    t[kG3] += s[kB1];                                                                       \
    t[kG4] += Ffy * s[kBs] + Fsy * s[kBf];                                                  \
    t[kChi2] += s[kCc];                                                                     \
    t[kChi2w] += s[kCw];                                                                    \
  } while (0)

// Scalar: one row at a time (any CPU).
[[maybe_unused]] void accumulateScalar(const Work& W, double F, double B, double sb2,
                                       double inv_gain, double* w_out, const double* w_prev,
                                       double* tot) {
  for (int r = 0; r < W.rows; ++r) {
    const std::size_t o =
        static_cast<std::size_t>((r / kLanes) * W.cols * kLanes + r % kLanes);
    const std::size_t ri = static_cast<std::size_t>(r);
    const double fy = W.fy[ri], Ffy = F * fy, Fdy = F * W.dy[ri], Fsy = F * W.sy[ri];
    double s[kNumSums] = {};
    for (int c = 0; c < W.cols; ++c) {
      const std::size_t i = o + static_cast<std::size_t>(c) * kLanes;
      const std::size_t j = static_cast<std::size_t>(c);
      const double m = Ffy * W.fx[j];
      const double w = W.use[i] / (sb2 + (m > 0 ? m * inv_gain : 0.0));
      w_out[i] = w;
      const double res = W.val[i] - B - m, wr = w * res;
      const double col[kA1 + 1] = {W.pdd[j], W.pdf[j], W.pds[j], W.dx[j], W.pff[j],
                                   W.pfs[j], W.fx[j],  W.pss[j], W.sx[j], 1.0};
      for (int k = 0; k <= kA1; ++k) s[k] += w * col[k];
      s[kBd] += wr * W.dx[j];
      s[kBf] += wr * W.fx[j];
      s[kBs] += wr * W.sx[j];
      s[kB1] += wr;
      s[kCc] += wr * res;
      s[kCw] += w_prev[i] * res * res;
    }
    ST_GAUSS_ADD_ROW(double, s, fy, Ffy, Fdy, Fsy, tot);
  }
}

#if defined(__SSE2__) && !defined(ST_DETECT_NO_SIMD)
// SSE2 (the x86-64 baseline): two rows per register, lanes {0, 1} and {2, 3} of each quad.
void accumulateSse2(const Work& W, double F, double B, double sb2, double inv_gain,
                    double* w_out, const double* w_prev, double* tot) {
  const __m128d vB = _mm_set1_pd(B), vsb2 = _mm_set1_pd(sb2), vig = _mm_set1_pd(inv_gain);
  const __m128d vF = _mm_set1_pd(F), zero = _mm_setzero_pd();
  const double *fx = W.fx.data(), *dx = W.dx.data(), *sx = W.sx.data();
  const double *pdd = W.pdd.data(), *pdf = W.pdf.data(), *pds = W.pds.data();
  const double *pff = W.pff.data(), *pfs = W.pfs.data(), *pss = W.pss.data();
  const int cols = W.cols, quads = W.quads;
  __m128d t[kNumTotals];
  for (auto& x : t) x = zero;
  for (int h = 0; h < quads * 2; ++h) {  // half-quads: rows 2h, 2h + 1
    const std::size_t o = static_cast<std::size_t>((h / 2) * cols * kLanes + (h % 2) * 2);
    const double* val = W.val.data() + o;
    const double* use = W.use.data() + o;
    const double* wp = w_prev + o;
    double* wo = w_out + o;
    const __m128d fy = _mm_loadu_pd(W.fy.data() + 2 * h);
    const __m128d Ffy = _mm_mul_pd(vF, fy);
    const __m128d Fdy = _mm_mul_pd(vF, _mm_loadu_pd(W.dy.data() + 2 * h));
    const __m128d Fsy = _mm_mul_pd(vF, _mm_loadu_pd(W.sy.data() + 2 * h));
    __m128d cc = zero, cw = zero, bd = zero, bf = zero, bs = zero, b1 = zero;
    for (int c = 0; c < cols; ++c) {
      const std::size_t i = static_cast<std::size_t>(c) * kLanes;
      const __m128d f = _mm_load1_pd(fx + c);
      const __m128d m = _mm_mul_pd(Ffy, f);
      const __m128d var = _mm_add_pd(vsb2, _mm_mul_pd(_mm_max_pd(m, zero), vig));
      const __m128d w = _mm_div_pd(_mm_loadu_pd(use + i), var);
      _mm_storeu_pd(wo + i, w);
      const __m128d res = _mm_sub_pd(_mm_sub_pd(_mm_loadu_pd(val + i), vB), m);
      const __m128d wr = _mm_mul_pd(w, res);
      cc = _mm_add_pd(cc, _mm_mul_pd(wr, res));
      cw = _mm_add_pd(cw, _mm_mul_pd(_mm_loadu_pd(wp + i), _mm_mul_pd(res, res)));
      bd = _mm_add_pd(bd, _mm_mul_pd(wr, _mm_load1_pd(dx + c)));
      bf = _mm_add_pd(bf, _mm_mul_pd(wr, f));
      bs = _mm_add_pd(bs, _mm_mul_pd(wr, _mm_load1_pd(sx + c)));
      b1 = _mm_add_pd(b1, wr);
    }
    __m128d s[kNumSums];
    s[kA1] = s[kAs] = s[kAss] = s[kAf] = s[kAfs] = s[kAff] = s[kAd] = s[kAds] = s[kAdf] =
        s[kAdd] = zero;
    for (int c = 0; c < cols; ++c) {
      const __m128d w = _mm_loadu_pd(wo + static_cast<std::size_t>(c) * kLanes);
      s[kAdd] = _mm_add_pd(s[kAdd], _mm_mul_pd(w, _mm_load1_pd(pdd + c)));
      s[kAdf] = _mm_add_pd(s[kAdf], _mm_mul_pd(w, _mm_load1_pd(pdf + c)));
      s[kAds] = _mm_add_pd(s[kAds], _mm_mul_pd(w, _mm_load1_pd(pds + c)));
      s[kAd] = _mm_add_pd(s[kAd], _mm_mul_pd(w, _mm_load1_pd(dx + c)));
      s[kAff] = _mm_add_pd(s[kAff], _mm_mul_pd(w, _mm_load1_pd(pff + c)));
      s[kAfs] = _mm_add_pd(s[kAfs], _mm_mul_pd(w, _mm_load1_pd(pfs + c)));
      s[kAf] = _mm_add_pd(s[kAf], _mm_mul_pd(w, _mm_load1_pd(fx + c)));
      s[kAss] = _mm_add_pd(s[kAss], _mm_mul_pd(w, _mm_load1_pd(pss + c)));
      s[kAs] = _mm_add_pd(s[kAs], _mm_mul_pd(w, _mm_load1_pd(sx + c)));
      s[kA1] = _mm_add_pd(s[kA1], w);
    }
    s[kBd] = bd, s[kBf] = bf, s[kBs] = bs, s[kB1] = b1, s[kCc] = cc, s[kCw] = cw;
    ST_GAUSS_ADD_ROW(__m128d, s, fy, Ffy, Fdy, Fsy, t);
  }
  for (int i = 0; i < kNumTotals; ++i)
    tot[i] = _mm_cvtsd_f64(_mm_add_sd(t[i], _mm_unpackhi_pd(t[i], t[i])));
}
#endif

#if defined(__GNUC__) && defined(__x86_64__) && !defined(ST_DETECT_NO_AVX2)
#define ST_GAUSS_AVX2 1
// AVX2 + FMA, chosen at run time: four rows per register, fused multiply-adds.
__attribute__((target("avx2,fma"))) void accumulateAvx2(const Work& W, double F, double B,
                                                        double sb2, double inv_gain,
                                                        double* w_out, const double* w_prev,
                                                        double* tot) {
  const __m256d vB = _mm256_set1_pd(B), vsb2 = _mm256_set1_pd(sb2);
  const __m256d vig = _mm256_set1_pd(inv_gain), vF = _mm256_set1_pd(F);
  const __m256d zero = _mm256_setzero_pd();
  const double *fx = W.fx.data(), *dx = W.dx.data(), *sx = W.sx.data();
  const double *pdd = W.pdd.data(), *pdf = W.pdf.data(), *pds = W.pds.data();
  const double *pff = W.pff.data(), *pfs = W.pfs.data(), *pss = W.pss.data();
  const int cols = W.cols, quads = W.quads;
  __m256d t[kNumTotals];
  for (auto& x : t) x = zero;
  for (int q = 0; q < quads; ++q) {
    const std::size_t o = static_cast<std::size_t>(q * cols * kLanes);
    const double* val = W.val.data() + o;
    const double* use = W.use.data() + o;
    const double* wp = w_prev + o;
    double* wo = w_out + o;
    const __m256d fy = _mm256_loadu_pd(W.fy.data() + kLanes * q);
    const __m256d Ffy = _mm256_mul_pd(vF, fy);
    const __m256d Fdy = _mm256_mul_pd(vF, _mm256_loadu_pd(W.dy.data() + kLanes * q));
    const __m256d Fsy = _mm256_mul_pd(vF, _mm256_loadu_pd(W.sy.data() + kLanes * q));
    __m256d cc = zero, cw = zero, bd = zero, bf = zero, bs = zero, b1 = zero;
    for (int c = 0; c < cols; ++c) {
      const std::size_t i = static_cast<std::size_t>(c) * kLanes;
      const __m256d f = _mm256_broadcast_sd(fx + c);
      const __m256d m = _mm256_mul_pd(Ffy, f);
      const __m256d var = _mm256_fmadd_pd(_mm256_max_pd(m, zero), vig, vsb2);
      const __m256d w = _mm256_div_pd(_mm256_loadu_pd(use + i), var);
      _mm256_storeu_pd(wo + i, w);
      const __m256d res = _mm256_sub_pd(_mm256_sub_pd(_mm256_loadu_pd(val + i), vB), m);
      const __m256d wr = _mm256_mul_pd(w, res);
      cc = _mm256_fmadd_pd(wr, res, cc);
      cw = _mm256_fmadd_pd(_mm256_loadu_pd(wp + i), _mm256_mul_pd(res, res), cw);
      bd = _mm256_fmadd_pd(wr, _mm256_broadcast_sd(dx + c), bd);
      bf = _mm256_fmadd_pd(wr, f, bf);
      bs = _mm256_fmadd_pd(wr, _mm256_broadcast_sd(sx + c), bs);
      b1 = _mm256_add_pd(b1, wr);
    }
    __m256d s[kNumSums];
    s[kA1] = s[kAs] = s[kAss] = s[kAf] = s[kAfs] = s[kAff] = s[kAd] = s[kAds] = s[kAdf] =
        s[kAdd] = zero;
    for (int c = 0; c < cols; ++c) {
      const __m256d w = _mm256_loadu_pd(wo + static_cast<std::size_t>(c) * kLanes);
      s[kAdd] = _mm256_fmadd_pd(w, _mm256_broadcast_sd(pdd + c), s[kAdd]);
      s[kAdf] = _mm256_fmadd_pd(w, _mm256_broadcast_sd(pdf + c), s[kAdf]);
      s[kAds] = _mm256_fmadd_pd(w, _mm256_broadcast_sd(pds + c), s[kAds]);
      s[kAd] = _mm256_fmadd_pd(w, _mm256_broadcast_sd(dx + c), s[kAd]);
      s[kAff] = _mm256_fmadd_pd(w, _mm256_broadcast_sd(pff + c), s[kAff]);
      s[kAfs] = _mm256_fmadd_pd(w, _mm256_broadcast_sd(pfs + c), s[kAfs]);
      s[kAf] = _mm256_fmadd_pd(w, _mm256_broadcast_sd(fx + c), s[kAf]);
      s[kAss] = _mm256_fmadd_pd(w, _mm256_broadcast_sd(pss + c), s[kAss]);
      s[kAs] = _mm256_fmadd_pd(w, _mm256_broadcast_sd(sx + c), s[kAs]);
      s[kA1] = _mm256_add_pd(s[kA1], w);
    }
    s[kBd] = bd, s[kBf] = bf, s[kBs] = bs, s[kB1] = b1, s[kCc] = cc, s[kCw] = cw;
    ST_GAUSS_ADD_ROW(__m256d, s, fy, Ffy, Fdy, Fsy, t);
  }
  for (int i = 0; i < kNumTotals; ++i) {
    const __m128d h = _mm_add_pd(_mm256_castpd256_pd128(t[i]), _mm256_extractf128_pd(t[i], 1));
    tot[i] = _mm_cvtsd_f64(_mm_add_sd(h, _mm_unpackhi_pd(h, h)));
  }
}

bool haveAvx2() {
  static const bool ok = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  return ok;
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

void evaluate(const StarPatch& P, const V5& p, Work& W, double* w_out, const double* w_prev,
              Normal& N) {
  pixelGaussianRow(W.cols, P.origin.x, p[0], p[4], W.fx.data(), W.dx.data(), W.sx.data());
  pixelGaussianRow(W.rows, P.origin.y, p[1], p[4], W.fy.data(), W.dy.data(), W.sy.data());
  for (int c = 0; c < W.cols; ++c) {
    const std::size_t i = static_cast<std::size_t>(c);
    const double f = W.fx[i], d = W.dx[i], s = W.sx[i];
    W.pdd[i] = d * d;
    W.pdf[i] = d * f;
    W.pds[i] = d * s;
    W.pff[i] = f * f;
    W.pfs[i] = f * s;
    W.pss[i] = s * s;
  }
  const double F = p[2], B = p[3];
  const double sb2 = P.sigma_bg * P.sigma_bg, inv_gain = 1.0 / P.gain;
  double tot[kNumTotals] = {};
#if defined(ST_GAUSS_AVX2)
  if (haveAvx2())
    accumulateAvx2(W, F, B, sb2, inv_gain, w_out, w_prev, tot);
  else
#endif
#if defined(__SSE2__) && !defined(ST_DETECT_NO_SIMD)
    accumulateSse2(W, F, B, sb2, inv_gain, w_out, w_prev, tot);
#else
    accumulateScalar(W, F, B, sb2, inv_gain, w_out, w_prev, tot);
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

// A star smeared by L px during the exposure (shorter than a streak) and fitted with the round
// PSF: its image has second moments s0^2 + L^2/12 along the smear and s0^2 across, and the round
// fit's sigma s sits in between, s^2 ~ s0^2 + L^2/24. The Fisher information of the round
// model along the smear is then that of a profile narrower than the star's: the variance along
// it is short by (s0^2 + L^2/12) / s^2 = 1 + L^2 / (24 s^2) (measured: tests/detect/
// test_blurred_stars.cpp; 1.15 at L = 1.9 px, s0 = 1 px). Across, the model's profile is wider
// than the star's, but the mis-specified fit does not reach the narrower profile's precision
// either (measured 0.95-1.0): left as it is, on the safe side.
void widenAlongSmear(const Vec2& smear, double s, Mat2& cov) {
  const double L2 = smear.squaredNorm();
  if (!(L2 > 0) || !(s > 0)) return;
  const Vec2 u = smear / std::sqrt(L2);
  cov += (L2 / (24.0 * s * s)) * u.dot(cov * u) * (u * u.transpose());
}

bool finite5(const V5& v) {
  for (double x : v)
    if (!std::isfinite(x)) return false;
  return true;
}

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

class GaussFitCentroider final : public Centroider {
 public:
  std::string name() const override { return "gauss"; }

 private:
  bool doCentroid(const StarPatch& P, Centroid& out, std::string* reason) const override {
    const cv::Mat1f& v = P.values;
    const double ox = P.origin.x, oy = P.origin.y;
    // Start: the background-subtracted centre of gravity (seed 004 eq. 4.1), flux its sum.
    thread_local Work work;
    const Work::Sums start = work.reset(P);
    const double sw = start.sw, sx = start.sx, sy = start.sy, peak = start.peak;
    const int unsaturated = start.unsaturated;
    if (!(sw > 0)) {
      if (reason) *reason = "no flux above background";
      return false;
    }
    // Start: the caller's first position when it is inside the window (the centre of light
    // of the pixels above the threshold: 0.10 px from the solution on the real frames, where
    // the window's CoG, moved by the noise of every pixel, is 0.21 px off; 2.75 instead of
    // 3.15 evaluations per star), else the CoG.
    const bool guess_inside = P.guess.x() >= ox && P.guess.y() >= oy &&
                              P.guess.x() <= ox + v.cols - 1 && P.guess.y() <= oy + v.rows - 1;
    V5 p = {guess_inside ? P.guess.x() : ox + sx / sw, guess_inside ? P.guess.y() : oy + sy / sw,
            std::max(sw, peak), P.background,
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
    double* w_cur = work.w_cur.data();
    double* w_trial = work.w_trial.data();
    // The normal equations at the estimate (N) and at a trial (T): swapped, not copied.
    Normal nbuf[2];
    Normal* N = &nbuf[0];
    Normal* T = &nbuf[1];
    // Levenberg-Marquardt from p; N holds the normal equations at the last accepted estimate.
    // The factor of the converged step's normal equations, for the covariance when their
    // damping is negligible (<= 1e-4 relative: the covariance is then off by <= 0.01 %).
    Ldl5 factor;  // of the damped normal equations of the last trial
    bool have_converged = false;
    auto fit = [&] {
      have_converged = false;
      evaluate(P, p, work, w_cur, w_trial /* no previous weights: chi2_prev unused */, *N);
      double lambda = 1e-3;
      double gd_prev = 0;  // predicted chi2 decrease of the last accepted step
      for (int it = 0; it < kMaxTrials; ++it) {
        M5 A;
        std::copy(&N->H[0][0], &N->H[0][0] + 25, &A[0][0]);
        for (int k = 0; k < 5; ++k) A[k][k] *= 1.0 + lambda;
        V5 d;
        if (!factorLdl5(A, factor)) {
          lambda *= 10;
          if (lambda > 1e8) break;
          continue;
        }
        ldlSolve5(factor, N->g, d);
        if (!finite5(d)) break;
        V5 q;
        for (int k = 0; k < 5; ++k) q[k] = p[k] + d[k];
        q[4] = std::clamp(q[4], 0.25, 20.0);
        double gd = 0;
        for (int k = 0; k < 5; ++k) gd += N->g[k] * d[k];
        // Error left after taking d: the next step, r * d with r^2 ~ gd / gd_prev (the
        // measured contraction of the last step, trusted once it is clearly contracting).
        const double rate2 = gd_prev > 0 ? gd / gd_prev : 1.0;
        if ((d[0] * d[0] + d[1] * d[1] < kStepTolPx * kStepTolPx &&
             std::abs(d[4]) < kStepTolSigma) ||
            gd < kStepTolChi2 || (rate2 < kMaxRate2 && gd * rate2 < kStepTolChi2)) {
          std::copy(q, q + 5, p);  // converged: the last step is too small to need checking
          have_converged = lambda <= 1e-4;
          break;
        }
        evaluate(P, q, work, w_trial, w_cur, *T);
        // Accept when the chi2 with the current weights does not grow (a fixed weighted
        // least-squares problem on both sides of the comparison).
        if (T->chi2_prev <= N->chi2_self + 1e-12) {
          std::copy(q, q + 5, p);
          std::swap(N, T);
          std::swap(w_cur, w_trial);
          gd_prev = gd;
          lambda = std::max(lambda * 0.1, 1e-7);
        } else {
          lambda *= 10;
          if (lambda > 1e8) break;
        }
      }
    };
    fit();
    // A pixel the model cannot explain (a hot pixel, a cosmic ray) pulls the fit towards it:
    // drop the worst pixel beyond kOutlierSigma and fit again, a few times at most.
    // Looked for only when the fit's chi2 is high enough to hold one: an 8-sigma pixel adds
    // 64 to it, a good fit gives n - 5 +- sqrt(2 (n - 5)); the search costs a pass.
    for (int dropped = 0; P.reject_spikes && dropped < kMaxOutliers && finite5(p) &&
                          N->chi2_self > work.usable() - 5 + 0.5 * kOutlierSigma * kOutlierSigma &&
                          dropOutlier(P, p, work);
         ++dropped)
      fit();
    if (!finite5(p) || !(p[2] > 0) || p[0] < ox - 0.5 || p[1] < oy - 0.5 ||
        p[0] > ox + v.cols - 0.5 || p[1] > oy + v.rows - 0.5 || p[4] >= 20.0) {
      if (reason) *reason = "PSF fit diverged";
      return false;
    }
    // Covariance: the inverse of the Fisher information J^T W J (Cramer-Rao), columns x, y, F.
    Ldl5& L = factor;
    V5 cx, cy, cf;
    const V5 ex = {1, 0, 0, 0, 0}, ey = {0, 1, 0, 0, 0}, ef = {0, 0, 1, 0, 0};
    if (!have_converged && !factorLdl5(N->H, L)) {
      if (reason) *reason = "PSF fit singular";
      return false;
    }
    ldlSolve5(L, ex, cx);
    ldlSolve5(L, ey, cy);
    ldlSolve5(L, ef, cf);
    if (!finite5(cx) || !finite5(cy) || !finite5(cf) || !(cx[0] > 0) || !(cy[1] > 0) ||
        !(cf[2] > 0)) {
      if (reason) *reason = "PSF fit singular";
      return false;
    }
    out.px = Vec2(p[0], p[1]);
    out.cov_px << cx[0], 0.5 * (cx[1] + cy[0]), 0.5 * (cx[1] + cy[0]), cy[1];
    widenAlongSmear(P.smear, p[4], out.cov_px);
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

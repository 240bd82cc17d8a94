// Normal equations of one pass of the "gauss" fit over the pixels (gauss_fit.cpp's header
// says why they are built this way: separable model, column sums, one pass per trial).
#include <algorithm>
#include <cmath>
#include <vector>

#if defined(__SSE2__) && !defined(ST_DETECT_NO_SIMD)
#include <emmintrin.h>
#endif
#if defined(__GNUC__) && defined(__x86_64__) && !defined(ST_DETECT_NO_AVX2)
#include <immintrin.h>
#endif

#include "sensors/detect/gauss_fit_internal.hpp"
#include "sensors/detect/pixel_gaussian.hpp"

namespace st::gauss_fit_detail {
namespace {

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

}  // namespace

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

}  // namespace st::gauss_fit_detail

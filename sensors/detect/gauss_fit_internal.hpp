/// @file gauss_fit_internal.hpp
/// Internal to the "gauss" centroider (gauss_fit.cpp): the 5-parameter LM state (x, y, flux F,
/// background B, PSF sigma s), its per-fit buffers, the normal equations of one pass
/// (gauss_fit_normal.cpp) and the spike rejection (gauss_fit_spikes.cpp).
#pragma once
#include <algorithm>
#include <cmath>
#include <vector>

#include "sensors/detect/centroider.hpp"

namespace st::gauss_fit_detail {

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

inline bool factorLdl5(const M5& A, Ldl5& F) {
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
inline void ldlSolve5(const Ldl5& F, const V5& b, V5& x) {
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

inline bool finite5(const V5& v) {
  for (double x : v)
    if (!std::isfinite(x)) return false;
  return true;
}

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

/// Fills N at p (tables of W for p), the weights at p in w_out.
void evaluate(const StarPatch& P, const V5& p, Work& W, double* w_out, const double* w_prev,
              Normal& N);

/// Marks the worst outlier pixel at p unusable (gauss_fit_spikes.cpp); false if there is none.
bool dropOutlier(const StarPatch& P, const V5& p, Work& W);

}  // namespace st::gauss_fit_detail

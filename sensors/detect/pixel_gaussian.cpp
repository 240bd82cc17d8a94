#include "sensors/detect/pixel_gaussian.hpp"

#include <cmath>
#include <vector>

#if defined(__GNUC__) && defined(__x86_64__) && !defined(ST_DETECT_NO_AVX2)
#include <immintrin.h>
#endif

namespace st {
namespace {

constexpr double kInvSqrt2 = 0.70710678118654752440;
constexpr double kInvSqrt2Pi = 0.39894228040143267794;

// Upper tail Q(u) = P(N(0,1) > u) and density phi(u) on u = i / kPerUnit, 0 <= u <= kMaxU,
// with their derivatives Q' = -phi and phi' = -u phi for the cubic Hermite interpolation.
// Step 1/32: interpolation error <= h^4/384 * max|d4| ~ 3e-9 (phi), 1.4e-9 (Q).
constexpr int kPerUnit = 32;
constexpr double kMaxU = 10.0;  // Q(10) = 7.6e-24, phi(10) = 7.7e-23: zero beyond

struct Node {
  double q, phi, dphi;
};

const std::vector<Node>& table() {
  static const std::vector<Node> t = [] {
    const int n = static_cast<int>(kMaxU * kPerUnit) + 2;
    std::vector<Node> v(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) {
      const double u = static_cast<double>(i) / kPerUnit;
      const double phi = kInvSqrt2Pi * std::exp(-0.5 * u * u);
      v[static_cast<std::size_t>(i)] = {0.5 * std::erfc(u * kInvSqrt2), phi, -u * phi};
    }
    return v;
  }();
  return t;
}

// Q(|u|) and phi(u).
inline void tailAndDensity(const Node* t, double u, double& q, double& phi) {
  const double a = std::abs(u) * kPerUnit;
  if (!(a < kMaxU * kPerUnit)) {
    q = 0;
    phi = 0;
    return;
  }
  const int i = static_cast<int>(a);
  const double x = a - i, x2 = x * x, x3 = x2 * x;
  const double h00 = 2 * x3 - 3 * x2 + 1, h10 = (x3 - 2 * x2 + x) / kPerUnit;
  const double h01 = -2 * x3 + 3 * x2, h11 = (x3 - x2) / kPerUnit;
  const Node& n0 = t[i];
  const Node& n1 = t[i + 1];
  q = h00 * n0.q - h10 * n0.phi + h01 * n1.q - h11 * n1.phi;
  phi = h00 * n0.phi + h10 * n0.dphi + h01 * n1.phi + h11 * n1.dphi;
}

}  // namespace

PixelGaussian1d pixelGaussian1d(double a, double x, double s) {
  const double up = (a + 0.5 - x) / s, lo = (a - 0.5 - x) / s;
  const double phi_up = kInvSqrt2Pi * std::exp(-0.5 * up * up);
  const double phi_lo = kInvSqrt2Pi * std::exp(-0.5 * lo * lo);
  PixelGaussian1d r;
  r.f = 0.5 * (std::erf(up * kInvSqrt2) - std::erf(lo * kInvSqrt2));
  r.df_dx = -(phi_up - phi_lo) / s;           // d/dx Phi((b-x)/s) = -phi/s
  r.df_ds = -(up * phi_up - lo * phi_lo) / s;  // d/ds Phi(u/s) = -(u/s) phi / s
  return r;
}

namespace {

// Pixels from their edges: pixel k lies between edge k and edge k + 1, with the normal CDF
// cdf[], density phi[] and standardised position u[] at each edge. The CDF difference has an
// absolute error ~1e-16, all the model F * f needs (the tables are good to ~1e-9).
inline void pixelsFromEdges(int n, double inv_s, const double* u, const double* cdf,
                            const double* phi, double* f, double* df_dx, double* df_ds) {
  for (int k = 0; k < n; ++k) {
    f[k] = cdf[k + 1] - cdf[k];
    df_dx[k] = -(phi[k + 1] - phi[k]) * inv_s;              // d/dx Phi((b-x)/s) = -phi/s
    df_ds[k] = -(u[k + 1] * phi[k + 1] - u[k] * phi[k]) * inv_s;  // d/ds Phi(u/s) = -(u/s) phi/s
  }
}

#if defined(__GNUC__) && defined(__x86_64__) && !defined(ST_DETECT_NO_AVX2)
// Four edges at a time: the table nodes are gathered, the Hermite basis is vector code.
__attribute__((target("avx2,fma"))) void edgesAvx2(int m, double u_first, double inv_s,
                                                   const Node* t, double* u, double* q,
                                                   double* phi) {
  const double* base = &t[0].q;
  const __m256d step = _mm256_set_pd(3, 2, 1, 0), vinv = _mm256_set1_pd(inv_s);
  const __m256d scale = _mm256_set1_pd(kPerUnit), inv_scale = _mm256_set1_pd(1.0 / kPerUnit);
  const __m256d amax = _mm256_set1_pd(kMaxU * kPerUnit), zero = _mm256_setzero_pd();
  const __m256d amax_in = _mm256_set1_pd(kMaxU * kPerUnit - 0.5);
  const __m256d two = _mm256_set1_pd(2), three = _mm256_set1_pd(3), one = _mm256_set1_pd(1);
  const __m256d sign = _mm256_set1_pd(-0.0);
  const __m256d all = _mm256_castsi256_pd(_mm256_set1_epi64x(-1));  // gather every lane
  for (int k = 0; k < m; k += 4) {
    const __m256d uu = _mm256_fmadd_pd(_mm256_add_pd(_mm256_set1_pd(k), step), vinv,
                                       _mm256_set1_pd(u_first));
    _mm256_storeu_pd(u + k, uu);
    const __m256d a = _mm256_mul_pd(_mm256_andnot_pd(sign, uu), scale);
    const __m256d inside = _mm256_cmp_pd(a, amax, _CMP_LT_OQ);
    const __m256d ac = _mm256_min_pd(a, amax_in);
    const __m128i i = _mm256_cvttpd_epi32(ac);
    const __m256d x = _mm256_sub_pd(ac, _mm256_cvtepi32_pd(i));
    const __m128i i3 = _mm_add_epi32(i, _mm_add_epi32(i, i));  // 3 doubles per node
    const __m256d x2 = _mm256_mul_pd(x, x), x3 = _mm256_mul_pd(x2, x);
    // h00 = 2x^3 - 3x^2 + 1, h01 = 1 - h00, h10 = (x^3 - 2x^2 + x)/32, h11 = (x^3 - x^2)/32
    const __m256d h00 = _mm256_fmadd_pd(two, x3, _mm256_fnmadd_pd(three, x2, one));
    const __m256d h01 = _mm256_sub_pd(one, h00);
    const __m256d h11 = _mm256_mul_pd(_mm256_sub_pd(x3, x2), inv_scale);
    const __m256d h10 = _mm256_fmadd_pd(_mm256_sub_pd(x, x2), inv_scale, h11);
    const __m256d q0 = _mm256_mask_i32gather_pd(zero, base, i3, all, 8);
    const __m256d p0 = _mm256_mask_i32gather_pd(zero, base + 1, i3, all, 8);
    const __m256d d0 = _mm256_mask_i32gather_pd(zero, base + 2, i3, all, 8);
    const __m256d q1 = _mm256_mask_i32gather_pd(zero, base + 3, i3, all, 8);
    const __m256d p1 = _mm256_mask_i32gather_pd(zero, base + 4, i3, all, 8);
    const __m256d d1 = _mm256_mask_i32gather_pd(zero, base + 5, i3, all, 8);
    __m256d qq = _mm256_fmadd_pd(h00, q0, _mm256_mul_pd(h01, q1));
    qq = _mm256_fnmadd_pd(h10, p0, _mm256_fnmadd_pd(h11, p1, qq));
    __m256d pp = _mm256_fmadd_pd(h00, p0, _mm256_mul_pd(h01, p1));
    pp = _mm256_fmadd_pd(h10, d0, _mm256_fmadd_pd(h11, d1, pp));
    qq = _mm256_blendv_pd(zero, qq, inside);  // upper tail of |u|
    // CDF at u: the tail for u < 0, 1 - tail otherwise.
    const __m256d neg = _mm256_cmp_pd(uu, zero, _CMP_LT_OQ);
    _mm256_storeu_pd(q + k, _mm256_blendv_pd(_mm256_sub_pd(one, qq), qq, neg));
    _mm256_storeu_pd(phi + k, _mm256_blendv_pd(zero, pp, inside));
  }
}

bool haveAvx2() {
  static const bool ok = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  return ok;
}
#endif

}  // namespace

void pixelGaussianRow(int n, double a0, double x, double s, double* f, double* df_dx,
                      double* df_ds) {
  const Node* t = table().data();
  const double inv_s = 1.0 / s;
  const double u_first = (a0 - 0.5 - x) * inv_s;
  // Edge values: n + 1 edges, rounded up to whole vectors.
  thread_local std::vector<double> u, q, phi;
  const std::size_t m = static_cast<std::size_t>(n + 1 + 3) & ~std::size_t{3};
  if (u.size() < m) {
    u.resize(m);
    q.resize(m);
    phi.resize(m);
  }
#if defined(__GNUC__) && defined(__x86_64__) && !defined(ST_DETECT_NO_AVX2)
  if (haveAvx2()) {
    edgesAvx2(static_cast<int>(m), u_first, inv_s, t, u.data(), q.data(), phi.data());
    pixelsFromEdges(n, inv_s, u.data(), q.data(), phi.data(), f, df_dx, df_ds);
    return;
  }
#endif
  for (int k = 0; k <= n; ++k) {
    const std::size_t i = static_cast<std::size_t>(k);
    u[i] = u_first + k * inv_s;
    tailAndDensity(t, u[i], q[i], phi[i]);
    if (u[i] >= 0) q[i] = 1.0 - q[i];  // CDF
  }
  pixelsFromEdges(n, inv_s, u.data(), q.data(), phi.data(), f, df_dx, df_ds);
}

}  // namespace st

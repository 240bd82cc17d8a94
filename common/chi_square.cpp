#include "common/chi_square.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "common/check.hpp"

namespace st {

namespace {

constexpr double kEps = 1e-16;
constexpr int kMaxIter = 10000;

/// Series for P(a, x), converges fast for x < a + 1.
double gammaPSeries(double a, double x, double log_gamma_a) {
  double ap = a, sum = 1.0 / a, del = sum;
  for (int n = 0; n < kMaxIter; ++n) {
    ap += 1.0;
    del *= x / ap;
    sum += del;
    if (std::abs(del) < std::abs(sum) * kEps) break;
  }
  return sum * std::exp(-x + a * std::log(x) - log_gamma_a);
}

/// Continued fraction for Q(a, x) = 1 - P(a, x) (modified Lentz), for x >= a + 1.
double gammaQContinuedFraction(double a, double x, double log_gamma_a) {
  const double tiny = std::numeric_limits<double>::min() / kEps;
  double b = x + 1.0 - a, c = 1.0 / tiny, d = 1.0 / b, h = d;
  for (int i = 1; i < kMaxIter; ++i) {
    const double an = -i * (i - a);
    b += 2.0;
    d = an * d + b;
    if (std::abs(d) < tiny) d = tiny;
    c = b + an / c;
    if (std::abs(c) < tiny) c = tiny;
    d = 1.0 / d;
    const double del = d * c;
    h *= del;
    if (std::abs(del - 1.0) < kEps) break;
  }
  return std::exp(-x + a * std::log(x) - log_gamma_a) * h;
}

}  // namespace

double regularizedGammaP(double a, double x) {
  if (x <= 0) return 0.0;
  const double lg = std::lgamma(a);
  if (x < a + 1.0) return gammaPSeries(a, x, lg);
  return 1.0 - gammaQContinuedFraction(a, x, lg);
}

double regularizedGammaQ(double a, double x) {
  if (x <= 0) return 1.0;
  const double lg = std::lgamma(a);
  if (x < a + 1.0) return 1.0 - gammaPSeries(a, x, lg);
  return gammaQContinuedFraction(a, x, lg);
}

double chiSquareCdf(double x, double dof) { return regularizedGammaP(0.5 * dof, 0.5 * x); }

double chiSquareQuantile(double p, double dof) {
  if (!(p > 0.0) || !(p < 1.0) || !(dof > 0)) return std::numeric_limits<double>::quiet_NaN();
  const double a = 0.5 * dof;
  const double lg = std::lgamma(a);
  // Wilson-Hilferty start: x = k (1 - 2/(9k) + z sqrt(2/(9k)))^3 with z the normal quantile
  // from Abramowitz & Stegun 26.2.23 (|err| < 4.5e-4); the iteration below makes the start's
  // accuracy irrelevant.
  const double pp = p < 0.5 ? p : 1.0 - p;
  const double t = std::sqrt(-2.0 * std::log(pp));
  double z = t - (2.515517 + 0.802853 * t + 0.010328 * t * t) /
                     (1.0 + 1.432788 * t + 0.189269 * t * t + 0.001308 * t * t * t);
  if (p < 0.5) z = -z;
  const double h = 2.0 / (9.0 * dof);
  double x = dof * std::pow(std::max(1.0 - h + z * std::sqrt(h), 1e-3), 3);
  // Small-dof lower tail: P(a, y) ~ y^a / Gamma(a+1) gives a better start.
  if (x <= 0 || (dof < 2 && p < 0.5)) x = 2.0 * std::exp((std::log(p) + std::lgamma(a + 1.0)) / a);
  // Bracket [lo, hi] kept for bisection when a Halley step leaves it.
  double lo = 0, hi = std::numeric_limits<double>::infinity();
  for (int it = 0; it < 200; ++it) {
    // Upper half: compare tails, Q(x) vs 1 - p (exact in floating point for p >= 0.5), so
    // quantiles near 1 keep their relative accuracy.
    const double f =
        p < 0.5 ? chiSquareCdf(x, dof) - p : (1.0 - p) - regularizedGammaQ(0.5 * dof, 0.5 * x);
    if (f < 0)
      lo = x;
    else
      hi = x;
    // Density of chi-square(dof) at x, in log form for range safety.
    const double y = 0.5 * x;
    const double logpdf = (a - 1.0) * std::log(y) - y - lg - std::log(2.0);
    const double pdf = std::exp(logpdf);
    double step = pdf > 0 ? f / pdf : 0.0;
    // Halley correction: f'' / f' = (a - 1)/x - 1/2 for the chi-square density.
    const double curv = (a - 1.0) / x - 0.5;
    const double denom = 1.0 - 0.5 * step * curv;
    if (denom > 0.5) step /= denom;
    double next = x - step;
    if (!(next > lo) || !(next < hi) || pdf == 0)
      next = std::isfinite(hi) ? 0.5 * (lo + hi) : 2.0 * std::max(x, 1.0);
    if (std::abs(next - x) <= 1e-15 * std::max(1.0, x)) return next;
    x = next;
  }
  return x;
}

double chiSquareUpperTail(double x, double dof) {
  if (!(dof > 0) || !(x > 0)) return 1.0;
  return std::clamp(regularizedGammaQ(0.5 * dof, 0.5 * x), 0.0, 1.0);
}

ChiSquareThresholds::ChiSquareThresholds(double alpha, int max_dof) {
  ST_ASSERT(alpha > 0 && alpha < 1 && max_dof >= 1);
  x_.resize(static_cast<std::size_t>(max_dof));
  for (int k = 1; k <= max_dof; ++k) x_[k - 1] = chiSquareQuantile(1.0 - alpha, k);
}

double ChiSquareThresholds::operator()(int dof) const {
  ST_ASSERT(dof >= 1 && dof <= maxDof());
  return x_[static_cast<std::size_t>(dof - 1)];
}

}  // namespace st

#include "sensors/detect/pixel_gaussian.hpp"

#include <cmath>

namespace st {

PixelGaussian1d pixelGaussian1d(double a, double x, double s) {
  constexpr double kInvSqrt2 = 0.70710678118654752440;
  constexpr double kInvSqrt2Pi = 0.39894228040143267794;
  const double up = (a + 0.5 - x) / s, lo = (a - 0.5 - x) / s;
  const double phi_up = kInvSqrt2Pi * std::exp(-0.5 * up * up);
  const double phi_lo = kInvSqrt2Pi * std::exp(-0.5 * lo * lo);
  PixelGaussian1d r;
  r.f = 0.5 * (std::erf(up * kInvSqrt2) - std::erf(lo * kInvSqrt2));
  r.df_dx = -(phi_up - phi_lo) / s;           // d/dx Phi((b-x)/s) = -phi/s
  r.df_ds = -(up * phi_up - lo * phi_lo) / s;  // d/ds Phi(u/s) = -(u/s) phi / s
  return r;
}

}  // namespace st

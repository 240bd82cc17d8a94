/// @file pixel_gaussian.hpp
/// The 1-D Gaussian PSF integrated over one pixel, with its derivatives, for the maximum-
/// likelihood fit (seed 004 eq. 4.7/4.8 with the Gaussian of eq. 4.11):
///   f(a; x, s) = Phi((a + 0.5 - x)/s) - Phi((a - 0.5 - x)/s)
/// The same model as st::pixelFraction1d in sensors/sim/psf.hpp (detection does not link
/// the simulator); the 2-D fraction is f(i; x, s) * f(j; y, s).
#pragma once

namespace st {

struct PixelGaussian1d {
  double f;      ///< fraction of the light on the pixel
  double df_dx;  ///< d f / d centre
  double df_ds;  ///< d f / d sigma
};

/// Pixel centred at `a`, PSF centre `x`, sigma `s` > 0 (all in px).
PixelGaussian1d pixelGaussian1d(double a, double x, double s);

}  // namespace st

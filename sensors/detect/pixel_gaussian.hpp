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

/// Pixel centred at `a`, PSF centre `x`, sigma `s` > 0 (all in px). Exact (libm erf/exp):
/// the reference for pixelGaussianRow.
PixelGaussian1d pixelGaussian1d(double a, double x, double s);

/// The same for the `n` consecutive pixels centred at a0, a0 + 1, ..., written to f[k],
/// df_dx[k], df_ds[k]: each pixel edge (shared by two pixels) is evaluated once, and the
/// normal tail probability and density come from a cubic Hermite table (|error| < 1e-8 on
/// f and the derivatives, see the test), several times cheaper than erfc + exp; with AVX2
/// (chosen at run time) four edges at a time.
void pixelGaussianRow(int n, double a0, double x, double s, double* f, double* df_dx,
                      double* df_ds);

}  // namespace st

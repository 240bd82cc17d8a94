/// @file seed004_psf.hpp
/// Seed 004's "psfWidth" (Tables 4.1, 5.2, 7.1): the width that holds the star's light, four
/// sigmas of its Gaussian PSF (eq. 4.13). One reading for every experiment of the seed
/// (centroid-defocus, magnitude-error): issue 38's D1 found one of them reading it as the FWHM,
/// a PSF 1.7x wider than the thesis'.
#pragma once

namespace st::app::mc {

constexpr double kSeed004PsfWidthSigmas = 4;  ///< psfWidth = 4 sigma (seed 004 eq. 4.13)

/// The Gaussian sigma [px] of a seed 004 psfWidth [px].
constexpr double seed004PsfSigma(double psf_width_px) { return psf_width_px / kSeed004PsfWidthSigmas; }

}  // namespace st::app::mc

/// @file wcs_header.hpp
/// `solve --wcs FILE`: the solved frame's FITS WCS as a FITS file without data (a primary
/// header, NAXIS = 0, as astrometry.net's .wcs files), which astropy.wcs and ds9 read.
///  - frame: always astrometric (RADESYS ICRS): a WCS maps pixels to catalog coordinates,
///    whatever frame the solution was reported in;
///  - pixels: FITS pixel (1, 1) is the centre of the input's first pixel (x = 0, y = 0 in
///    solve's star table, row 0 the first row of the file), also for a flipped parity;
///  - projection: TAN about the camera's principal point; with a distorted camera
///    RA---TAN-SIP with A/B (pixel -> sky) and AP/BP (sky -> pixel) of order 5. CD and the
///    SIP terms are one least-squares fit of the camera model (distortion, mirrored parity,
///    fx != fy) over a 41 x 41 grid of the image; the largest fit error is a COMMENT card.
#pragma once
#include <string>

#include "solve/solve_output.hpp"

namespace st::solve {

/// Throws InputError naming --wcs when the file cannot be written.
void writeWcsHeader(const SolveReport& r, const std::string& path);

}  // namespace st::solve

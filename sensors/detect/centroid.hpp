/// @file centroid.hpp
/// One detected star on the image: its position with a covariance from the noise model, its
/// brightness and quality flags. Produced by detection (star_detector.hpp), consumed by
/// identification and tracking as weighted observations.
#pragma once
#include <cstdint>
#include <string>

#include "common/attitude.hpp"

namespace st {

/// Quality flags of a centroid (bit set). Flagged stars are kept unless the detector options
/// ask to reject them, so that downstream stages can decide (e.g. streaks during a slew).
enum CentroidFlag : uint32_t {
  kSaturated = 1,     ///< at least one pixel at the saturation level: position less reliable
  kTouchesEdge = 2,   ///< the blob touches the image border: light lost, position biased
  kElongated = 4,     ///< second moments far from round: streak, double star or artefact
  kHotPixel = 8,      ///< a single bright pixel, or a saturated cluster, with dark neighbours
  kExtended = 16,     ///< wider than any PSF across its narrow axis: foreground, glow, edge
  /// Its light spread over more pixels than this frame's stars spread theirs (flux over peak
  /// well above their median; full-frame detection): a lamp, a lit window, a mottled
  /// foreground's bright patch. Kept, but ranked after the point-like stars.
  kDiffuse = 32,
  /// Sharper than this frame's PSF (a radiation hit: a charged particle's charge in one to a
  /// few pixels, no optics in between), or a short sharp track (full-frame detection). Kept,
  /// but ranked after every star and never used to build a lost-in-space pattern.
  kRadiationHit = 64,
};

/// "saturated,hit" and the like: the set flags' short names, "-" for none.
std::string centroidFlagNames(uint32_t flags);

struct Centroid {
  Vec2 px = Vec2::Zero();      ///< [px] position, conventions.hpp pixel convention
  Mat2 cov_px = Mat2::Zero();  ///< [px^2] covariance from the noise model
  double flux = 0;             ///< background-subtracted sum [ADU]
  double peak = 0;             ///< max pixel above background [ADU]
  double snr = 0;              ///< flux / its 1-sigma noise
  int area = 0;                ///< pixels in the blob
  uint32_t flags = 0;          ///< CentroidFlag bits
  /// [px^2] second central moments of the blob's light above the background (full-frame
  /// detection; zero from windows): a streak's direction and length.
  Mat2 shape = Mat2::Zero();
};

}  // namespace st

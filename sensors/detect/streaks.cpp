#include "sensors/detect/streaks.hpp"

#include <algorithm>
#include <cmath>

#include "sensors/detect/star_detector.hpp"

namespace st {

void measureStreaks(const cv::Mat& image, const std::function<Vec2(const Vec2&)>& blur_at,
                    StarDetector& detector, std::vector<Centroid>& stars) {
  const double psf = detector.options().psfSigmaGuess();
  std::vector<PredictedStar> streaks;
  std::vector<std::size_t> index;
  for (std::size_t k = 0; k < stars.size(); ++k) {
    const Vec2 blur = blur_at(stars[k].px);
    if (blur.norm() <= 2.0 * psf) continue;
    // The centroid of a fragment lies on the streak, at most half its length from the
    // middle: the window (5 sigma + 3 psf + blur/2) then holds the whole streak.
    PredictedStar p;
    p.px = stars[k].px;
    p.cov_px = std::pow(0.25 * blur.norm(), 2) * Mat2::Identity();
    p.blur_px = blur;
    p.anchor_at_px = true;
    streaks.push_back(p);
    index.push_back(k);
  }
  if (streaks.empty()) return;
  const std::vector<WindowResult> found = detector.centroidWindows(image, streaks);
  const std::vector<Centroid> detected = stars;
  std::vector<bool> drop(stars.size(), false);
  for (std::size_t j = 0; j < found.size(); ++j) {
    if (!found[j].centroid) {
      drop[index[j]] = true;  // no streak around this blob (noise, a hot pixel)
      continue;
    }
    // A blob in the centroid window (half-size 2.5 psf + blur/2) off this streak's segment
    // is another star whose light pulls the CoG: the star is left out (a blend). Fragments
    // of the streak itself lie on the segment.
    const Vec2 c = found[j].centroid->px, b = streaks[j].blur_px;
    const Vec2 u = b.normalized();
    const double reach = 2.5 * psf + 0.5 * b.norm() + 3.0 * psf;
    for (const Centroid& o : detected) {
      const Vec2 d = o.px - c;
      if (d.cwiseAbs().maxCoeff() > reach) continue;
      const double along = std::abs(d.dot(u)), across = std::abs(u.x() * d.y() - u.y() * d.x());
      if (across > 3.0 * psf || along > 0.5 * b.norm() + 3.0 * psf) drop[index[j]] = true;
    }
    if (!drop[index[j]]) stars[index[j]] = *found[j].centroid;
  }
  // Fragments of one streak now share one centroid: keep the first (brightest) of each.
  std::vector<Centroid> kept;
  for (std::size_t k = 0; k < stars.size(); ++k) {
    if (drop[k]) continue;
    bool dup = false;
    for (const Centroid& o : kept)
      dup = dup || (o.px - stars[k].px).norm() < 2.0 * psf;
    if (!dup) kept.push_back(stars[k]);
  }
  stars = std::move(kept);
}

namespace {

/// [px] the length a blob's second moments give: a streak of length L along a PSF of sigma s
/// has L^2/12 + s^2 along and s^2 across, so L = sqrt(12 (l1 - l2)).
double streakLength(const Centroid& c) {
  const double a = c.shape(0, 0), b = c.shape(1, 1), x = c.shape(0, 1);
  return std::sqrt(12.0 * 2.0 * std::sqrt(0.25 * (a - b) * (a - b) + x * x));  // l1 - l2
}

/// Twice the blob's major axis angle (an axis has no sign).
double twiceAxisAngle(const Centroid& c) {
  return std::atan2(2.0 * c.shape(0, 1), c.shape(0, 0) - c.shape(1, 1));
}

/// [px] the extent along `u` of the streak that blob `k` (of length `length`) belongs to: a
/// faint or shallow streak breaks where the noise dips below the threshold, and its pieces are
/// blobs on one line, each shorter than the streak. Pieces within `across_px` of the line and
/// `gap_px` of the growing segment's ends join it. Never shorter than `length`.
double chainedLength(const std::vector<Centroid>& stars, std::size_t k, double length,
                     const Vec2& u, double across_px, double gap_px) {
  double lo = -0.5 * length, hi = 0.5 * length;
  std::vector<bool> joined(stars.size(), false);
  joined[k] = true;
  for (bool grew = true; grew;) {
    grew = false;
    for (std::size_t j = 0; j < stars.size(); ++j) {
      if (joined[j]) continue;
      const Vec2 d = stars[j].px - stars[k].px;
      if (std::abs(u.x() * d.y() - u.y() * d.x()) > across_px) continue;
      const double half = 0.5 * streakLength(stars[j]);
      const double a = d.dot(u) - half, b = d.dot(u) + half;
      if (a > hi + gap_px || b < lo - gap_px) continue;
      lo = std::min(lo, a);
      hi = std::max(hi, b);
      joined[j] = grew = true;
    }
  }
  return hi - lo;
}

}  // namespace

// A rotation across the boresight streaks all stars alike. The brightest elongated blobs give
// the streak: each its length (its own, or the extent of the pieces on its line when the
// streak broke apart: a piece can outshine a whole faint streak) and its axis. Whole streaks
// share one length; so the length is the one most of them agree on (the longer of two
// equally supported), with at least kMinAgree agreeing, and their axes must agree too, or
// nothing is returned (a roll, a tumble, double stars). Without the pieces joined, the
// lengths of pieces set it on 2 of 150 frames of a 4 deg/s slew (4.7 and 5.2 px for 13 px
// streaks), and the rate drawn from them made those fixes 4-8x too confident
// (StreakShapes.PiecesOfAStreakDoNotSetItsLength).
std::optional<Vec2> streakFromShapes(const std::vector<Centroid>& stars,
                                     const DetectorOptions& opts) {
  constexpr int kUse = 5;                // brightest elongated blobs used
  constexpr int kMinAgree = 3;           // of them sharing one length
  constexpr double kMinCoherence = 0.9;  // resultant length of the doubled axis angles
  const double psf = opts.psfSigmaGuess();
  struct Shape {
    double length, twice_angle;
  };
  std::vector<Shape> shapes;
  for (std::size_t k = 0; k < stars.size(); ++k) {  // brightest first
    const Centroid& c = stars[k];
    if (static_cast<int>(shapes.size()) >= kUse) break;
    if (!(c.flags & kElongated) || (c.flags & (kSaturated | kTouchesEdge))) continue;
    const double twice = twiceAxisAngle(c);
    const Vec2 u(std::cos(0.5 * twice), std::sin(0.5 * twice));
    // Pieces: on the line within a PSF's reach, gaps of up to a few PSF widths.
    shapes.push_back({chainedLength(stars, k, streakLength(c), u, 1.5 * psf, 3.0 * psf), twice});
  }
  // Two whole streaks' moment lengths differ by their noise: ~1 px or a tenth of the length.
  auto agree = [](double l1, double l2) {
    return std::abs(l1 - l2) <= std::max(1.5, 0.15 * std::max(l1, l2));
  };
  int best_support = 0;
  double best_len = 0;
  for (const Shape& s : shapes) {
    int support = 0;
    for (const Shape& o : shapes) support += agree(s.length, o.length);
    if (support > best_support || (support == best_support && s.length > best_len)) {
      best_support = support;
      best_len = s.length;
    }
  }
  if (best_support < kMinAgree) return std::nullopt;
  std::vector<double> lengths;
  double c2 = 0, s2 = 0;
  for (const Shape& s : shapes) {
    if (!agree(best_len, s.length)) continue;
    lengths.push_back(s.length);
    c2 += std::cos(s.twice_angle);
    s2 += std::sin(s.twice_angle);
  }
  const double n = static_cast<double>(lengths.size());
  if (std::hypot(c2, s2) / n < kMinCoherence) return std::nullopt;
  std::nth_element(lengths.begin(), lengths.begin() + lengths.size() / 2, lengths.end());
  const double len = lengths[lengths.size() / 2];
  if (len <= 2.0 * psf) return std::nullopt;
  const double angle = 0.5 * std::atan2(s2, c2);
  return Vec2(len * std::cos(angle), len * std::sin(angle));
}

}  // namespace st

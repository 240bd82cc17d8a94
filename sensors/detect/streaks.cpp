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

// A rotation across the boresight streaks all stars alike. A streak of length L along a PSF
// of sigma s has second moments L^2/12 + s^2 along and s^2 across, so L = sqrt(12 (l1 - l2)).
// The brightest elongated blobs are whole streaks (faint ones break into fragments): their
// median length, and the mean of their axes (doubled angles: an axis has no sign), must
// agree, or nothing is returned (a roll, a tumble, double stars).
std::optional<Vec2> streakFromShapes(const std::vector<Centroid>& stars,
                                     const DetectorOptions& opts) {
  constexpr int kUse = 5;              // brightest elongated blobs used
  constexpr double kMinCoherence = 0.9;  // resultant length of the doubled axis angles
  std::vector<double> lengths;
  double c2 = 0, s2 = 0;
  for (const Centroid& c : stars) {  // brightest first
    if (static_cast<int>(lengths.size()) >= kUse) break;
    if (!(c.flags & kElongated) || (c.flags & (kSaturated | kTouchesEdge))) continue;
    const double a = c.shape(0, 0), b = c.shape(1, 1), x = c.shape(0, 1);
    const double dd = std::sqrt(0.25 * (a - b) * (a - b) + x * x);
    lengths.push_back(std::sqrt(12.0 * 2.0 * dd));  // l1 - l2 = 2 dd
    const double twice = std::atan2(2.0 * x, a - b);  // twice the major axis angle
    c2 += std::cos(twice);
    s2 += std::sin(twice);
  }
  if (lengths.size() < 3) return std::nullopt;
  const double n = static_cast<double>(lengths.size());
  if (std::hypot(c2, s2) / n < kMinCoherence) return std::nullopt;
  std::nth_element(lengths.begin(), lengths.begin() + lengths.size() / 2, lengths.end());
  const double len = lengths[lengths.size() / 2];
  const double psf = opts.psfSigmaGuess();
  if (len <= 2.0 * psf) return std::nullopt;
  const double angle = 0.5 * std::atan2(s2, c2);
  return Vec2(len * std::cos(angle), len * std::sin(angle));
}

}  // namespace st

/// @file streaks.hpp
/// Streaks of a rotating camera in full-frame detection. A faint streak breaks into
/// fragments that detectStars reports as separate, displaced stars; these functions re-measure
/// each star over its whole streak, from a known blur (a measured rate) or from the blobs'
/// own shapes (no rate).
#pragma once
#include <functional>
#include <optional>
#include <vector>

#include <opencv2/core.hpp>

#include "sensors/detect/centroid.hpp"
#include "sensors/detect/detector_options.hpp"

namespace st {

class StarDetector;

/// Re-measures the full-frame centroids of streaks over the whole streak `blur_at` gives at
/// each star's pixel (fragments of a faint streak merged into one centroid; blends with
/// another star, and blobs with no streak around them, dropped). Round stars are untouched.
void measureStreaks(const cv::Mat& image, const std::function<Vec2(const Vec2&)>& blur_at,
                    StarDetector& detector, std::vector<Centroid>& stars);

/// Without a rate, the streak (length and direction [px]) every star draws, from the shapes
/// of the brightest elongated blobs; nothing when they disagree (a roll, a tumble, doubles).
std::optional<Vec2> streakFromShapes(const std::vector<Centroid>& stars,
                                     const DetectorOptions& opts);

}  // namespace st

/// @file fov_search.hpp
/// Lost-in-space identification when the focal length is unknown (a plate solve from the
/// image alone): try a geometric grid of horizontal fields of view; each try widens the
/// pair tolerances and gates by the relative scale uncertainty of the grid step
/// (IdentifyOptions::scale_tolerance). The first verified solution's matched stars then fit
/// the focal length (least squares, principal point at the centre, square pixels), and the
/// identification is repeated with the fitted camera and no scale slack.
#pragma once
#include <chrono>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "sensors/identify/camera_refine.hpp"
#include "sensors/identify/identifier.hpp"

namespace st {

/// False-match threshold of the candidate pass made with scale slack (its gates are wide);
/// the accepted answer always passes IdentifyOptions::verify.false_match_threshold.
constexpr double kCandidateFalseMatchThreshold = 1e-2;

/// Horizontal FOVs [rad] from `min_hfov` to `max_hfov` whose ranges
/// [f (1 - s), f (1 + s)] touch each other (s = scale_tolerance).
std::vector<double> fovSearchGrid(double min_hfov, double max_hfov, double scale_tolerance);

/// What a search may accept and how long it may run (solve's --ra/--dec/--radius and
/// --cpulimit). The default accepts every verified solution and never stops early.
struct SearchLimits {
  /// Returns "" to accept a verified solution, else why it is refused (e.g. outside the
  /// position hint); a refused solution counts as a failure and the search goes on.
  std::function<std::string(const IdentifyResult&)> refuse;
  std::optional<std::chrono::steady_clock::time_point> deadline;
  bool expired() const { return deadline && std::chrono::steady_clock::now() >= *deadline; }
};

/// The reason a search gives when SearchLimits::deadline stopped it.
constexpr const char* kCpuLimitReason = "cpu limit reached";

struct FovSearchResult {
  IdentifyResult result;             ///< of the final (fitted-camera) identification
  CameraModel camera;                ///< fitted camera (or the last one tried)
  std::vector<StarObservation> obs;  ///< observations with that camera
  int fovs_tried = 0;
  double search_ms = 0;              ///< total time of all tries [ms]
  bool cpu_limit_reached = false;    ///< the deadline stopped the search before its end
  std::string refused;               ///< why SearchLimits::refuse turned down the last solution
  /// The camera fit of the final matches when the policy refines (focal length, distortion
  /// with their uncertainties, residuals before/after); with a camera file, what it says
  /// about the file (describeDiscrepancy).
  std::optional<CameraFitResult> camera_fit;
  double model_error_px = 0;  ///< what the fitted camera leaves unexplained (camera_fit.hpp)
  bool healed = false;        ///< the given camera failed; a refined one solved
};

/// `identifier` options are used as given except scale_tolerance (set per try). The grid's
/// cameras have pixels `pixel_aspect` times taller than wide (fy = fx / pixel_aspect), and
/// their fit keeps fx and fy apart when that is not 1.
/// `min_sigma_px` floors the centroid sigma (toStarObservations): on a real image with an
/// approximate camera the model error (distortion, focal length) dominates the noise.
FovSearchResult identifyUnknownFov(const std::vector<Centroid>& centroids, int width,
                                   int height, const StarDatabase& db,
                                   StarIdentifier& identifier,
                                   const std::vector<double>& hfov_grid, double scale_tolerance,
                                   double min_sigma_px = 0.02, const SearchLimits& limits = {},
                                   double pixel_aspect = 1);

/// Identify with a camera as `policy` allows: as it is (fixed), or a candidate with scale
/// slack whose matches fit the camera (rounds of fit -> re-match), then the strict
/// identification with the fitted camera; a camera file is healed when it fails as it is.
/// Used by identifyUnknownFov, solve (--fov-deg, --camera) and the tracker's lost-in-space.
FovSearchResult identifyAndFit(const std::vector<Centroid>& centroids, const CameraModel& cam,
                               const StarDatabase& db, StarIdentifier& identifier,
                               const CameraFitPolicy& policy, double min_sigma_px = 0.02,
                               const SearchLimits& limits = {});

}  // namespace st

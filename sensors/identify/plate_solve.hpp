/// @file plate_solve.hpp
/// Lost-in-space on one frame with a plate solver's habits (astrometry.net's solve-field):
///  - both image parities: a mirrored image (bottom-up FITS, a flipped readout) has
///    left-handed star patterns that no rotation fits. The normal parity is tried first; the
///    mirrored one only when it fails, so a normal frame costs nothing more;
///  - a position hint: only a solution whose boresight lies within a radius is accepted;
///  - a deadline (SearchLimits::deadline) that stops the search between tries.
///
/// Parity "flipped" means the image is mirrored left-right (x -> width - 1 - x) with
/// respect to the sky as the camera sees it. Its solution is found by un-mirroring the
/// centroids, so the attitude is the proper rotation of the un-mirrored camera frame (the
/// frame of the camera file): a left-right mirrored copy of a frame gives the frame's own
/// attitude; a top-bottom mirrored copy gives the same boresight with the roll + 180 deg.
#pragma once
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "sensors/identify/fov_search.hpp"

namespace st {

enum class Parity { Normal, Flipped };
const char* toString(Parity p);  ///< "normal" / "flipped"

/// Which parities a search tries.
enum class ParityChoice { Normal, Flipped, Both };

/// Boresight hint: the solution's boresight must lie within `radius` of (ra, dec) [rad].
struct PositionHint {
  double ra = 0, dec = 0, radius = 0;
};

/// Angle [rad] between the boresight (camera +z) of attitude q_ic and the hint's centre.
double boresightDistance(const Quat& q_ic, const PositionHint& hint);

/// A SearchLimits::refuse that turns down solutions outside the hint, naming the distance.
std::function<std::string(const IdentifyResult&)> refuseOutsideHint(const PositionHint& hint);

/// Centroids mirrored left-right in an image `width` pixels wide (x -> width - 1 - x, the
/// mirror about the centre of the pixel grid, conventions.hpp); everything else kept.
std::vector<Centroid> mirrorLeftRight(const std::vector<Centroid>& centroids, int width);

struct PlateSolveResult {
  FovSearchResult search;  ///< of the parity that solved (or of the last one tried)
  Parity parity = Parity::Normal;
  int parities_tried = 0;
};

/// One search of the caller's choice (a known camera: identifyAndFit; an unknown FOV:
/// identifyUnknownFov) over the given centroids.
using CentroidSearch = std::function<FovSearchResult(const std::vector<Centroid>&)>;

/// Runs `search` on the centroids as they are (Normal), then mirrored (Flipped), as `choice`
/// allows, stopping at the first solution or when `limits` expired. search.obs[i].px of a
/// flipped solution are the un-mirrored pixels; the caller's centroids keep the image's.
PlateSolveResult solveBothParities(const std::vector<Centroid>& centroids, int width,
                                   ParityChoice choice, const SearchLimits& limits,
                                   const CentroidSearch& search);

/// The cameras a lost-in-space search tries: one camera with the fit its source allows (a
/// camera file healed when it fails, an approximate FOV refined, the tracker's camera as it
/// is), or, without one, a grid of horizontal FOVs.
struct LostInSpaceCameras {
  std::optional<CameraModel> camera;
  CameraFitPolicy policy = CameraFitPolicy::fixed();
  std::vector<double> fov_grid;  ///< [rad] when there is no camera
  double scale_tol = 0.02;
  double pixel_aspect = 1;  ///< of the grid's cameras: fy = fx / pixel_aspect
};

/// The one lost-in-space driver, used by `solve` (solve/identify_frame.cpp) and by the
/// tracker when it is lost (sensors/tracking/star_tracker.cpp): identify and fit with the
/// cameras given, over the parities `parity` allows, within `limits`. `sigma_floor_px`
/// floors the centroid sigma (the camera model's error on real frames). Centroids flagged
/// kRadiationHit (ranked last by detection) are left out: only the prefix before the first
/// is searched.
PlateSolveResult lostInSpace(const std::vector<Centroid>& centroids, int width, int height,
                             const StarDatabase& db, StarIdentifier& identifier,
                             const LostInSpaceCameras& cameras, double sigma_floor_px,
                             ParityChoice parity, const SearchLimits& limits = {});

}  // namespace st

/// @file camera_refine.hpp
/// Identification that adjusts the camera it is given (the plate solver's focal length and
/// distortion from the sky, the self-healing of an approximate camera file, the tracker's
/// online calibration): what may change (CameraFitPolicy) and the rounds "fit the camera to
/// the matched stars (sensors/camera/camera_fit.hpp) -> match again with the fitted camera"
/// that grow a candidate's matches from the centre, where any scale fits, to the corners,
/// where distortion shows.
#pragma once
#include <optional>
#include <vector>

#include "catalog/star_database.hpp"
#include "sensors/camera/camera_fit.hpp"
#include "sensors/identify/identifier.hpp"

namespace st {

struct CameraFitPolicy {
  /// Slack of the first (candidate) pass: the relative focal-length error it tolerates.
  double scale_tolerance = 0;
  bool fit_focal = false;  ///< refit the focal length from the matches
  /// and fx, fy apart (needs fit_focal): for non-square pixels, whose aspect on the sky a
  /// binning factor gives only nominally (the Swarm heads' 2x-binned rows are 1.93x taller
  /// than wide, measured on the sky)
  bool fit_aspect = false;
  int radial_terms = 0;    ///< and up to this many radial terms, where the stars support them
  std::optional<CameraPrior> prior;  ///< how far the given camera is trusted
  /// A camera file: identified as it is first; when that fails, again with scale slack at
  /// focal lengths up to +-heal_range from it, refined around it (prior), so that a focal
  /// length a few percent off or unmodelled distortion still solves.
  double heal_range = 0;

  bool refines() const { return fit_focal || radial_terms > 0; }
  /// The camera is right: identify with it as it is.
  static CameraFitPolicy fixed();
  /// An approximate field of view (--fov-deg, the FOV search): focal length, k1 and k2 free;
  /// fx and fy apart when the pixels are not square (pixel_aspect != 1).
  static CameraFitPolicy approximateFov(double scale_tolerance, double pixel_aspect = 1);
  /// A camera file: trusted first, healed when it fails, its discrepancy measured always;
  /// fx and fy apart when its pixels are not square.
  static CameraFitPolicy cameraFile(const CameraModel& cam);
};

/// The matched stars of `r` as the fit's input (pixels, catalog directions, pixel sigmas).
FrameStars frameStarsOf(const std::vector<StarObservation>& obs, const IdentifyResult& r,
                        const StarDatabase& db, const CameraModel& cam);

/// The fit `policy` allows to the matches of `r` (k terms chosen by the likelihood-ratio
/// test); focal length and distortion only (a principal point is not determined by one
/// narrow frame).
CameraFitResult fitCameraToMatches(const CameraModel& cam, const std::vector<StarObservation>& obs,
                                   const IdentifyResult& r, const StarDatabase& db,
                                   const CameraFitPolicy& policy);

/// The same fit of stars already gathered (one frame).
CameraFitResult fitCameraToStars(const CameraModel& cam, const FrameStars& stars,
                                 const CameraFitPolicy& policy);

struct RefinedCandidate {
  IdentifyResult result;             ///< the candidate with the matches of the last round
  CameraModel camera;                ///< fitted in the last round
  std::vector<StarObservation> obs;  ///< the centroids seen through that camera
  std::optional<CameraFitResult> fit;
};

/// Rounds of fit -> re-match (verification seeded with the candidate's matches, gates widened
/// by the fit's focal-length uncertainty, acceptance at the candidate threshold) until the
/// matches stop growing. The answer is still the caller's strict identification with the
/// returned camera: these rounds only find the camera.
RefinedCandidate refineFromCandidate(const std::vector<Centroid>& centroids,
                                     const CameraModel& cam, std::vector<StarObservation> obs,
                                     IdentifyResult candidate, const StarDatabase& db,
                                     const IdentifyOptions& id_options,
                                     const CameraFitPolicy& policy, double min_sigma_px);

}  // namespace st

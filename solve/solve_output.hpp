/// @file solve_output.hpp
/// What `solve` prints: the text report, or with --json exactly one JSON object on stdout
/// (built with nlohmann::ordered_json, so any file name or message is escaped). JSON schema:
///  - solved (exit 0): {"solved": true, "image", "input": "image"|"star list", "parity":
///    "normal"|"flipped", "ra_deg", "dec_deg", "roll_deg" (of the
///    boresight: the principal point), "centre_ra_deg", "centre_dec_deg" (of the image's
///    centre pixel), "q_ib": [w,x,y,z], "covariance"
///    (3x3, rad^2, camera frame), "sigma_cross_boresight_arcsec", "sigma_roll_arcsec",
///    "hfov_deg", "algorithm", "solver", "stars_detected", "stars_matched",
///    "rms_residual_arcsec", "rms_residual_px", "false_match_probability",
///    "hypotheses_tried", "fovs_tried", "epoch_jyear", "epoch_source", "database",
///    "database_epoch_jyear", "catalog" (the catalog's name), "catalog_id" ("HIP", "HR"),
///    "frame": "apparent" | "astrometric" (celestial_frame.hpp), "aberration_velocity_km_s"
///    [x, y, z] (ICRS axes; the observer's velocity the apparent frame is for, zero for
///    astrometric), "camera" (camera_report.hpp),
///    "residual_chi2" (the matched stars' residuals over their centroid sigmas, squared and
///    summed), "residual_dof" (2 n - 3: chi2 / dof near 1 for honest covariances),
///    "detection": {"radiation_hits" (flagged, kept, ranked last), "rejected_blobs",
///    "psf_width_px" [x, y] (the PSF's three-pixel width the hit rule measured, 0 unknown)},
///    "photometry": {"fitted", "exposure_s" (1: unknown to solve, the zero point holds it),
///    "zero_point", "zero_point_se", "colour_term", "colour_term_se" (null when not fitted),
///    "off_axis_exponent", "off_axis_exponent_fitted", "off_axis_exponent_se", "scatter_mag",
///    "robust_sigma_mag", "stars_used", "stars_clipped"} (or {"fitted": false, "reason"};
///    sensors/identify/photometry.hpp),
///    "stars": [{"id", "name" (e.g. "HR 5340"), "x", "y", "mag" (catalog V), "bv" (B-V or
///    null), "mag_inst", "mag_fitted", "mag_residual" (V - fitted), "photometry_used",
///    "residual_arcsec", "residual_px"}] (x, y in the input's pixels, also for a flipped
///    image), "timing_ms":
///    {"load", "detect", "database", "identify", "pattern", "verify", "total"}};
///  - not solved (exit 1): {"solved": false, "status" (IdentifyStatus or "error"),
///    "reason", "image", "stars_detected", "parities_tried", "cpu_limit_reached",
///    "detection" (as above), "exit_code": 1};
///  - an error ended the run: {"solved": false, "status": "error", "error": message,
///    "exit_code": 2 for bad input (file, flag, value), 1 otherwise}; in a batch also "image".
/// A batch prints one object per frame, one per line (JSON Lines), in input order.
#pragma once
#include <string>

#include <nlohmann/json.hpp>

#include "solve/celestial_frame.hpp"
#include "solve/frame_input.hpp"
#include "solve/solve_epoch.hpp"
#include "solve/solve_options.hpp"
#include "catalog/star_database.hpp"
#include "sensors/identify/plate_solve.hpp"

namespace st::solve {

struct SolveTimings {
  double load = 0, detect = 0, database = 0, identify = 0, total = 0;  ///< [ms]
};

/// Everything one run of `solve` reports.
struct SolveReport {
  const SolveOptions& o;
  const FrameInput& in;
  const StarDatabase& db;
  std::string db_source;  ///< the --database path, or how the in-memory one was built
  SolveEpoch epoch;
  PlateSolveResult ps;
  std::string failure;  ///< empty when solved
  bool focal_fitted = true;
  SolveTimings ms;
  CelestialFrame frame;  ///< the frame q_ib and RA/Dec are in
};

/// "HIP" for Hipparcos, "HR" for the Bright Star Catalogue, "TYC" for Tycho, else "ID":
/// from the catalog name a database records (BuildReport::catalog_name).
std::string catalogIdLabel(const std::string& catalog_name);

void printSolutionText(const SolveReport& r);
nlohmann::ordered_json solutionJson(const SolveReport& r);
nlohmann::ordered_json failureJson(const SolveReport& r);
nlohmann::ordered_json errorJson(const std::string& message, int exit_code);
/// The brightest `n` detections, and every radiation hit, with their shape measures (position, flux, peak, SNR, area,
/// sigma of the light along and across its long axis, peak over flux, flags), to stderr:
/// what `-v` shows to see why a frame did or did not solve.
void printDetections(const FrameInput& in, std::size_t n = 25);
/// `j` as one line of text, without the newline (invalid UTF-8 in a file name replaced).
std::string jsonLine(const nlohmann::ordered_json& j);
/// jsonLine on stdout.
void printJson(const nlohmann::ordered_json& j);

/// The annotated picture of a frame, solved or not (the image, or a black frame for a star
/// list): blobs marked by kind, identified stars named, the solution or why it failed.
void writeSolveAnnotation(const SolveReport& r, const std::string& path);

}  // namespace st::solve

// `startracker solve`: lost-in-space on one frame. Centroids (detected or listed) ->
// identification (any registered algorithm, over a FOV range when the camera is unknown,
// both parities, within a position hint and a time limit) -> attitude with covariance.
#include <chrono>
#include <cstdio>
#include <optional>

#include <opencv2/imgcodecs.hpp>

#include "app/command.hpp"
#include "app/output_file.hpp"
#include "app/solve/frame_input.hpp"
#include "app/solve/solve_epoch.hpp"
#include "app/solve/solve_options.hpp"
#include "app/solve/solve_output.hpp"
#include "catalog/database_recipe.hpp"
#include "catalog/star_catalog.hpp"
#include "common/conventions.hpp"
#include "common/errors.hpp"
#include "common/log.hpp"
#include "sensors/attitude/wahba.hpp"
#include "sensors/identify/fov_search.hpp"

namespace st::app {
namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

/// The cameras to try: one (--camera / --fov-deg) or a grid of horizontal FOVs.
struct CameraSearch {
  std::optional<CameraModel> fixed;
  bool fit_focal = true;  ///< a FOV without a camera file is approximate: fit the focal length
  std::vector<double> grid;
  double scale_tol = 0.02;
  double max_diag = 0;  ///< [rad] the widest image diagonal of the search
};

CameraSearch cameraSearch(const SolveOptions& o, int w, int h) {
  requireSolvableFov(o, w, h);
  CameraSearch cs;
  if (o.camera.given()) {
    cs.fixed = o.camera.resolve(w, h);
    cs.fit_focal = o.camera.camera_file.empty();
    cs.max_diag = 2 * cs.fixed->halfDiagonalFov();
    return cs;
  }
  if (o.fov_range_deg.size() != 2 || o.fov_range_deg[0] <= 0 ||
      o.fov_range_deg[1] < o.fov_range_deg[0])
    throw InputError("--fov-range needs MIN MAX in degrees with 0 < MIN <= MAX");
  cs.grid = fovSearchGrid(deg2rad(o.fov_range_deg[0]), deg2rad(o.fov_range_deg[1]), cs.scale_tol);
  cs.max_diag = 2 * CameraModel::fromFov(w, h, cs.grid.back()).halfDiagonalFov() * (1 + cs.scale_tol);
  return cs;
}

struct DatabaseChoice {
  StarDatabase db;
  std::string source;
  SolveEpoch epoch;
};

/// The --database file (refused when its epoch is too far from the observation's), or a
/// database built in memory for the camera search at the observation epoch.
DatabaseChoice database(const SolveOptions& o, const FrameInput& in, const CameraSearch& cs) {
  DatabaseChoice out;
  if (!o.database.empty()) {
    out.db = StarDatabase::load(o.database);
    out.source = o.database;
    out.epoch = chooseEpoch(o.epoch, in.epoch_jyear, in.epoch_source, &out.db);
    requireDatabaseEpoch(out.db, o.database, out.epoch);
    if (out.db.params().max_pair_angle < cs.max_diag * 0.999 && cs.fixed)
      log::warn(
          "%s holds pairs up to %.2f deg, the image diagonal is "
          "%.2f deg; stars far apart will not be paired",
          o.database.c_str(), rad2deg(out.db.params().max_pair_angle), rad2deg(cs.max_diag));
    return out;
  }
  out.epoch = chooseEpoch(o.epoch, in.epoch_jyear, in.epoch_source, nullptr);
  const StarCatalog cat = loadCatalog(StarDatabase::defaultCatalogPath());
  CameraDatabaseRecipe r;
  r.diagonal_fov_rad = cs.max_diag;
  // The finest pixel scale in the search: doubles unresolved at every FOV tried.
  r.pixel_scale_rad = cs.fixed ? cs.fixed->pixelScale()
                               : CameraModel::fromFov(in.width, in.height, cs.grid.front()).pixelScale();
  r.mag_limit = o.mag_limit;
  r.epoch_jyear = out.epoch.jyear;
  r.aberration = true;
  out.db = StarDatabase::build(cat, databaseParams(r));
  char b[300];
  std::snprintf(b, sizeof b, "built in memory from %s (V <= %.1f, epoch from %s)",
                StarDatabase::defaultCatalogPath().c_str(), o.mag_limit, out.epoch.source.c_str());
  out.source = b;
  return out;
}

PlateSolveResult identify(const SolveOptions& o, const FrameInput& in, const StarDatabase& db,
                          const CameraSearch& cs, Clock::time_point t_start) {
  IdentifyOptions io;
  io.solver = o.solver;
  io.max_stars = o.max_stars;
  std::string err;
  auto identifier = StarIdentifier::create(o.algorithm, io, &err);
  if (!identifier) throw InputError("--algorithm: " + err);
  if (!WahbaSolver::create(o.solver, &err)) throw InputError("--solver: " + err);
  const double sigma_floor =
      o.min_sigma_px >= 0 ? o.min_sigma_px : (o.camera.camera_file.empty() ? 0.5 : 0.1);
  SearchLimits limits;
  if (const auto hint = o.positionHint()) limits.refuse = refuseOutsideHint(*hint);
  if (o.cpulimit_s > 0)
    limits.deadline = t_start + std::chrono::duration_cast<Clock::duration>(
                                    std::chrono::duration<double>(o.cpulimit_s));
  const CentroidSearch search = [&](const std::vector<Centroid>& stars) {
    if (cs.fixed)  // an approximate FOV (no camera file) gets 1 % slack and a focal fit
      return identifyAndFit(stars, *cs.fixed, db, *identifier, cs.fit_focal ? 0.01 : 0.0,
                            cs.fit_focal, sigma_floor, limits);
    return identifyUnknownFov(stars, in.width, in.height, db, *identifier, cs.grid, cs.scale_tol,
                              sigma_floor, limits);
  };
  return solveBothParities(in.stars, in.width, o.parityChoice(), limits, search);
}

int solveAndReport(const SolveOptions& o, bool& printed) {
  const auto t_start = Clock::now();
  if (!o.annotate.empty()) {
    // Both checks before the work: a finished solve must not be lost to a typo.
    if (!cv::haveImageWriter(o.annotate))
      throw InputError("--annotate " + o.annotate +
                       ": not an image format OpenCV writes (use .png or .jpg)");
    prepareOutputFile(o.annotate, "--annotate");
  }
  o.positionHint();  // a bad hint fails before any work
  const FrameInput in = loadFrameInput(o);
  const CameraSearch cs = cameraSearch(o, in.width, in.height);
  auto t0 = Clock::now();
  DatabaseChoice dbc = database(o, in, cs);
  SolveReport rep{o, in, dbc.db, dbc.source, dbc.epoch, {}, {}, cs.fit_focal, {}};
  rep.ms.database = msSince(t0);
  rep.ms.load = in.load_ms;
  rep.ms.detect = in.detect_ms;
  t0 = Clock::now();
  if (!in.detection_reason.empty() || in.stars.size() < 3)
    rep.failure = "too few stars " + std::string(in.star_list ? "listed" : "detected") + " (" +
                  std::to_string(in.stars.size()) + ")" +
                  (in.detection_reason.empty() ? "" : ": " + in.detection_reason);
  else
    rep.ps = identify(o, in, dbc.db, cs, t_start);
  rep.ms.identify = msSince(t0);
  rep.ms.total = msSince(t_start);
  if (rep.failure.empty() && !rep.ps.search.result.solved()) rep.failure = rep.ps.search.result.reason;
  if (!rep.failure.empty()) {
    if (o.json) printJson(failureJson(rep));
    printed = true;
    log::error("%s: not solved: %s", o.input.c_str(), rep.failure.c_str());
    return kExitFailure;
  }
  if (o.json)
    printJson(solutionJson(rep));
  else
    printSolutionText(rep);
  printed = true;  // a failing --annotate below must not take the solution with it
  if (!o.annotate.empty()) writeSolveAnnotation(rep, o.annotate);
  return kExitOk;
}

}  // namespace

int runSolve(const SolveOptions& o) {
  bool printed = false;
  try {
    return solveAndReport(o, printed);
  } catch (const InputError& e) {
    // With --json the one object on stdout is solve's (main would print a second one).
    if (!o.json || printed) throw;
    log::error("%s", e.what());
    printJson(errorJson(e.what(), kExitUsage));
    return kExitUsage;
  } catch (const std::exception& e) {
    if (!o.json || printed) throw;
    log::error("%s", e.what());
    printJson(errorJson(e.what(), kExitFailure));
    return kExitFailure;
  }
}

}  // namespace st::app

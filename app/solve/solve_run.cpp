// `startracker solve`: lost-in-space on one frame of a run. Centroids (detected or listed) ->
// identification (any registered algorithm, over a FOV range when the camera is unknown,
// both parities, within a position hint and a time limit) -> attitude with covariance.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <optional>

#include <opencv2/imgcodecs.hpp>

#include "app/command.hpp"
#include "app/output_file.hpp"
#include "app/solve/camera_report.hpp"
#include "app/solve/frame_input.hpp"
#include "app/solve/identify_frame.hpp"
#include "app/solve/solve_epoch.hpp"
#include "app/solve/solve_options.hpp"
#include "app/solve/solve_output.hpp"
#include "app/solve/solve_run.hpp"
#include "app/solve/wcs_header.hpp"
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

/// The in-memory database's epoch: the observation epoch rounded to 1e-3 yr (8.8 h), so that
/// a night's frames share one database and a cache file serves a day. Stars move by at most
/// 0.07" in half a step (annual aberration 20.5" x 2 pi x 5e-4, proper motion 0.005"), well
/// inside kEpochToleranceArcsec.
double databaseEpoch(double jyear) { return std::round(jyear * 1000) / 1000; }

struct DatabaseChoice {
  const StarDatabase* db = nullptr;
  std::shared_ptr<const StarDatabase> held;
  std::string source;
  SolveEpoch epoch;
  double ms = 0;
};

/// The --database file (refused when its epoch is too far from the observation's), or the
/// database of the camera search at the observation epoch (built once, cached on disk).
DatabaseChoice database(const SolveOptions& o, const FrameInput& in, const CameraSearch& cs,
                        SolveSources& src) {
  DatabaseChoice out;
  if (src.file_db) {
    out.db = &*src.file_db;
    out.source = o.database;
    out.ms = src.file_db_ms;
    out.epoch = chooseEpoch(o.epoch, in.epoch_jyear, in.epoch_source, out.db);
    requireDatabaseEpoch(*out.db, o.database, out.epoch);
    if (out.db->params().max_pair_angle < cs.max_diag * 0.999 && cs.fixed)
      log::warn(
          "%s holds pairs up to %.2f deg, the image diagonal is "
          "%.2f deg; stars far apart will not be paired",
          o.database.c_str(), rad2deg(out.db->params().max_pair_angle), rad2deg(cs.max_diag));
    return out;
  }
  const auto t0 = Clock::now();
  out.epoch = chooseEpoch(o.epoch, in.epoch_jyear, in.epoch_source, nullptr);
  CameraDatabaseRecipe r;
  r.diagonal_fov_rad = cs.max_diag;
  // The finest pixel scale in the search: doubles unresolved at every FOV tried.
  r.pixel_scale_rad = cs.fixed ? cs.fixed->pixelScale()
                               : CameraModel::fromFov(in.width, in.height, cs.grid.front()).pixelScale();
  r.mag_limit = o.mag_limit;
  r.epoch_jyear = databaseEpoch(out.epoch.jyear);
  // Built in the requested frame's annual part; an observer velocity is applied afterwards.
  r.aberration = src.frame.annual;
  CachedDatabase c = src.cache.get(databaseParams(r));
  out.held = c.db;
  out.db = out.held.get();
  char b[400];
  std::snprintf(b, sizeof b, "%s from %s (V <= %.1f, epoch from %s)", c.how.c_str(),
                StarDatabase::defaultCatalogPath().c_str(), o.mag_limit, out.epoch.source.c_str());
  // e.g. "built in memory from catalog/data/hip_main_v6.6.dat.gz (V <= 6.6, epoch from today)"
  out.source = b;
  out.ms = msSince(t0);
  return out;
}

PlateSolveResult identify(const SolveOptions& o, const FrameInput& in, const StarDatabase& db,
                          const CameraSearch& cs, Clock::time_point t_start) {
  return identifyFrame(o, in.stars, in.width, in.height, db,
                       {cs.fixed, cs.fit_focal, cs.grid, cs.scale_tol}, o.positionHint(),
                       o.parityChoice(), t_start, "--");
}

}  // namespace

SolveSources::SolveSources(const SolveOptions& o)
    : cache(StarDatabase::defaultCatalogPath(), !o.no_cache), frame(requestedFrame(o)) {
  if (o.database.empty()) return;
  const auto t0 = Clock::now();
  file_db = StarDatabase::load(o.database);
  file_db_ms = msSince(t0);
}

std::unique_ptr<FrameOutcome> solveFrame(const SolveOptions& o_run, SolveSources& src) {
  const auto t_start = Clock::now();
  auto f = std::make_unique<FrameOutcome>();
  f->o = o_run;
  const SolveOptions& o = f->o;
  f->in = loadFrameInput(o);
  const FrameInput& in = f->in;
  const CameraSearch cs = cameraSearch(o, in.width, in.height);
  DatabaseChoice dbc = database(o, in, cs, src);
  f->db = dbc.held;
  f->rep.reset(
      new SolveReport{o, in, *dbc.db, dbc.source, dbc.epoch, {}, {}, cs.fit_focal, {}, src.frame});
  SolveReport& rep = *f->rep;
  rep.ms.database = dbc.ms;
  rep.ms.load = in.load_ms;
  rep.ms.detect = in.detect_ms;
  const auto t0 = Clock::now();
  if (!in.detection_reason.empty() || in.stars.size() < 3)
    rep.failure = "too few stars " + std::string(in.star_list ? "listed" : "detected") + " (" +
                  std::to_string(in.stars.size()) + ")" +
                  (in.detection_reason.empty() ? "" : ": " + in.detection_reason);
  else
    rep.ps = identify(o, in, *dbc.db, cs, t_start);
  if (rep.failure.empty() && rep.ps.search.result.solved())
    changeFrame(rep.ps.search.result, *dbc.db, databaseFrame(dbc.db->params()),
                dbc.db->params().epoch_jyear, src.frame, dbc.epoch.jyear);
  rep.ms.identify = msSince(t0);
  rep.ms.total = msSince(t_start);
  if (rep.failure.empty() && !rep.ps.search.result.solved()) rep.failure = rep.ps.search.result.reason;
  f->code = rep.failure.empty() ? kExitOk : kExitFailure;
  f->ms = rep.ms.total;
  return f;
}

int reportFrame(FrameOutcome& f) {
  const SolveOptions& o = f.o;
  if (!f.rep) {
    if (o.json) {
      nlohmann::ordered_json j = errorJson(f.error, f.code);
      j["image"] = o.input;
      printJson(j);
    }
    // Most messages name the file already (loadImage's do).
    if (f.error.rfind(o.input, 0) == 0)
      log::error("%s", f.error.c_str());
    else
      log::error("%s: %s", o.input.c_str(), f.error.c_str());
    return f.code;
  }
  const SolveReport& rep = *f.rep;
  if (!rep.failure.empty()) {
    if (o.json) printJson(failureJson(rep));
    log::error("%s: not solved: %s", o.input.c_str(), rep.failure.c_str());
    return kExitFailure;
  }
  if (const std::string d = cameraDiscrepancy(rep); !d.empty()) log::warn("%s", d.c_str());
  if (o.json)
    printJson(solutionJson(rep));
  else
    printSolutionText(rep);
  if (!o.wcs.empty()) writeWcsHeader(rep, o.wcs);
  if (!o.annotate.empty()) writeSolveAnnotation(rep, o.annotate);
  return kExitOk;
}

}  // namespace st::app

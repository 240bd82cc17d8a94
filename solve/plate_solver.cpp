// The plate solver: lost-in-space on one frame. Centroids (detected or listed) ->
// identification (any registered algorithm, over a FOV range when the camera is unknown,
// both parities, within a position hint and a time limit) -> attitude with covariance.
#include <chrono>
#include <future>
#include <cmath>
#include <cstdio>
#include <optional>

#include <opencv2/imgcodecs.hpp>

#include "solve/plate_solver.hpp"

#include "solve/camera_report.hpp"
#include "solve/frame_input.hpp"
#include "solve/identify_frame.hpp"
#include "solve/solve_epoch.hpp"
#include "solve/solve_options.hpp"
#include "solve/solve_output.hpp"
#include "catalog/database_recipe.hpp"
#include "catalog/star_catalog.hpp"
#include "common/conventions.hpp"
#include "common/errors.hpp"
#include "common/log.hpp"
#include "imageio/image_file.hpp"
#include "sensors/detect/dark_frame.hpp"
#include "solve/star_list.hpp"
#include "sensors/attitude/wahba.hpp"
#include "sensors/identify/fov_search.hpp"

namespace st::solve {

/// The cameras to try: one (--camera / --fov-deg) or a grid of horizontal FOVs.
struct CameraSearch {
  std::optional<CameraModel> fixed;
  bool fit_focal = true;  ///< a FOV without a camera file is approximate: fit the focal length
  std::vector<double> grid;
  double scale_tol = 0.02;
  double pixel_aspect = 1;  ///< of the grid's cameras (--pixel-aspect, --binning)
  double max_diag = 0;  ///< [rad] the widest image diagonal of the search
};

struct DatabaseChoice {
  std::shared_ptr<const StarDatabase> db;
  std::string source;
  SolveEpoch epoch;
  double ms = 0;
  bool before_frame = false;  ///< loaded before the frame's clock started (--database)
};

/// What solveFile chose from an image's header while the pixels were being decoded.
struct Prepared {
  CameraSearch cs;
  DatabaseChoice db;
};

namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}


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
  cs.pixel_aspect = o.camera.pixelAspect(o.option_prefix);
  cs.max_diag = 2 * CameraModel::fromFov(w, h, cs.grid.back(), cs.pixel_aspect).halfDiagonalFov() *
                (1 + cs.scale_tol);
  return cs;
}

/// The in-memory database's epoch: the observation epoch rounded to 1e-3 yr (8.8 h), so that
/// a night's frames share one database and a cache file serves a day. Stars move by at most
/// 0.07" in half a step (annual aberration 20.5" x 2 pi x 5e-4, proper motion 0.005"), well
/// inside kEpochToleranceArcsec.
double databaseEpoch(double jyear) { return std::round(jyear * 1000) / 1000; }

PlateSolveResult identify(const SolveOptions& o, const FrameInput& in, const StarDatabase& db,
                          const CameraSearch& cs, Clock::time_point t_start) {
  return identifyFrame(o, in.stars, in.width, in.height, db,
                       {cs.fixed, cs.fit_focal, cs.grid, cs.scale_tol, cs.pixel_aspect},
                       o.positionHint(),
                       o.parityChoice(), t_start);
}


}  // namespace

PlateSolver::PlateSolver(SolveOptions options)
    : o_(std::move(options)), frame_(requestedFrame(o_)) {
  o_.positionHint();  // a bad hint fails before any work
  // The pixels' shape on the sky, for detection: the camera file's (read again, once, per
  // solver: .ini cameras are handed to startracker-cli), else --pixel-aspect / --binning.
  pixel_aspect_ = o_.camera.camera_file.empty()
                      ? o_.camera.pixelAspect(o_.option_prefix)
                      : CameraModel::loadFile(o_.camera.camera_file, o_.camera.camera_section)
                            .pixelAspect();
  if (!o_.dark.empty() && o_.dark_frame.empty()) o_.dark_frame = readDarkFrame(o_.dark);
  if (o_.database.empty()) return;
  const auto t0 = Clock::now();
  given_db_ = std::make_shared<const StarDatabase>(StarDatabase::load(o_.database));
  given_source_ = o_.database;
  given_from_file_ = true;
  given_ms_ = msSince(t0);
}

PlateSolver::PlateSolver(SolveOptions options, std::shared_ptr<const StarDatabase> db,
                         std::string source, bool from_file)
    : PlateSolver(std::move(options)) {
  given_db_ = std::move(db);
  given_source_ = std::move(source);
  given_from_file_ = from_file;
}

std::unique_ptr<FrameOutcome> PlateSolver::solveFile(const std::string& path) const {
  const auto t_start = Clock::now();
  SolveOptions o = o_;
  o.input = path;
  // An image whose header gives its size (PNG, JPEG, TIFF, PNM) and whose epoch is known
  // before decoding (--epoch, or the file name) has its database chosen from those while
  // another thread decodes and detects: a plate solve per process loads its database from
  // the disk cache every time, and two cores do both at once.
  const std::optional<imageio::ImageProbe> probe =
      isStarList(path) || !o.dark_frame.empty() ? std::nullopt : imageio::probeImage(path);
  const double aspect = pixel_aspect_;
  if (!probe) return solveInput(loadFrameInput(o, aspect), path, t_start);
  auto decoded = std::async(std::launch::async, [&o, aspect] { return loadFrameInput(o, aspect); });
  std::optional<Prepared> early;
  try {
    CameraSearch cs = cameraSearch(o, probe->width, probe->height);
    DatabaseChoice db =
        database(o, cs, probe->width, probe->height, probe->epoch_jyear, probe->epoch_source,
                 t_start);
    early = Prepared{std::move(cs), std::move(db)};
  } catch (...) {
    early.reset();  // said again, in order, by the sequential path below
  }
  FrameInput in = decoded.get();
  if (in.width != probe->width || in.height != probe->height || in.epoch_jyear != probe->epoch_jyear)
    early.reset();  // the header said otherwise than the pixels: choose again
  return solveInput(std::move(in), path, t_start, early ? &*early : nullptr);
}

std::unique_ptr<FrameOutcome> PlateSolver::solveImage(const cv::Mat& image,
                                                      const std::string& name) const {
  const auto t_start = Clock::now();
  return solveInput(frameInputFromImage(image, o_, name, pixel_aspect_), name, t_start);
}

std::unique_ptr<FrameOutcome> PlateSolver::solveFileCaught(const std::string& path) const {
  const auto t0 = Clock::now();
  int code = kNotSolved;
  std::string error;
  try {
    return solveFile(path);
  } catch (const InputError& e) {
    code = kBadInput;
    error = e.what();
  } catch (const std::exception& e) {
    error = e.what();
  }
  auto f = std::make_unique<FrameOutcome>();
  f->o = o_;
  f->o.input = path;
  f->code = code;
  f->error = error;
  f->ms = msSince(t0);
  return f;
}

/// The --database file (refused when its epoch is too far from the observation's), or the
/// database of the camera search at the observation epoch (built once, cached on disk).
DatabaseChoice PlateSolver::database(const SolveOptions& o, const CameraSearch& cs, int width,
                                     int height, const std::optional<double>& epoch_jyear,
                                     const std::string& epoch_source,
                                     Clock::time_point t_start) const {
  DatabaseChoice dbc;
  if (given_db_) {
    dbc.db = given_db_;
    dbc.source = given_source_;
    // Loaded before the frame's clock started: counted once, and added to that frame's total
    // (issue 39: "total" was smaller than its "database" part).
    dbc.ms = given_counted_->exchange(true) ? 0.0 : given_ms_;
    dbc.before_frame = true;
    dbc.epoch = chooseEpoch(o.epoch, epoch_jyear, epoch_source,
                            given_from_file_ ? dbc.db.get() : nullptr);
    if (given_from_file_) requireDatabaseEpoch(*dbc.db, given_source_, dbc.epoch);
    if (dbc.db->params().max_pair_angle < cs.max_diag * 0.999 && cs.fixed)
      log::warn(
          "%s holds pairs up to %.2f deg, the image diagonal is "
          "%.2f deg; stars far apart will not be paired",
          given_source_.c_str(), rad2deg(dbc.db->params().max_pair_angle), rad2deg(cs.max_diag));
  } else {
    const auto t0 = Clock::now();
    dbc.epoch = chooseEpoch(o.epoch, epoch_jyear, epoch_source, nullptr);
    CameraDatabaseRecipe r;
    r.diagonal_fov_rad = cs.max_diag;
    // The finest pixel scale in the search: doubles unresolved at every FOV tried.
    r.pixel_scale_rad = cs.fixed ? cs.fixed->pixelScale()
                                 : CameraModel::fromFov(width, height, cs.grid.front(),
                                                        cs.pixel_aspect).pixelScale();
    r.mag_limit = o.mag_limit;
    r.epoch_jyear = databaseEpoch(dbc.epoch.jyear);
    // Built in the requested frame's annual part; an observer velocity is applied afterwards.
    r.aberration = frame_.annual;
    std::string how;
    // --cpulimit holds inside the build too: a wide field's database takes a minute once.
    StarDatabase::StopFn stop;
    const auto deadline =
        t_start + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(o.cpulimit_s));
    if (o.cpulimit_s > 0) stop = [deadline] { return Clock::now() >= deadline; };
    try {
      dbc.db = cameraDatabase(r, "", !o.no_cache, &how, stop);
    } catch (const BuildStopped&) {
      char m[320];
      std::snprintf(m, sizeof m,
                    "cpu limit reached (%scpulimit %g s) while building the star database of a "
                    "%.1f deg diagonal; run once without the limit (the database is then cached) "
                    "or give one from `startracker catalog build` with %sdatabase",
                    o.option_prefix.c_str(), o.cpulimit_s, rad2deg(cs.max_diag),
                    o.option_prefix.c_str());
      throw ProcessingError(m);
    }
    char b[400];
    std::snprintf(b, sizeof b, "%s from %s (V <= %.1f, epoch from %s)", how.c_str(),
                  StarDatabase::defaultCatalogPath().c_str(), o.mag_limit, dbc.epoch.source.c_str());
    // e.g. "built in memory from catalog/data/hip_main_v6.6.dat.gz (V <= 6.6, epoch from today)"
    dbc.source = b;
    dbc.ms = msSince(t0);
  }
  return dbc;
}

std::unique_ptr<FrameOutcome> PlateSolver::solveInput(FrameInput in, const std::string& name,
                                                      Clock::time_point t_start,
                                                      const Prepared* early) const {
  auto f = std::make_unique<FrameOutcome>();
  f->o = o_;
  f->o.input = name;
  f->in = std::move(in);
  const SolveOptions& o = f->o;
  const FrameInput& fin = f->in;
  // The camera search and database chosen from the header when they were (solveFile), so
  // that a camera file is not read again.
  const CameraSearch cs = early ? early->cs : cameraSearch(o, fin.width, fin.height);
  const DatabaseChoice dbc =
      early ? early->db
            : database(o, cs, fin.width, fin.height, fin.epoch_jyear, fin.epoch_source, t_start);
  f->db = dbc.db;
  const StarDatabase& db = *dbc.db;
  f->rep.reset(new SolveReport{o, fin, db, dbc.source, dbc.epoch, {}, {}, cs.fit_focal, {}, frame_});
  SolveReport& rep = *f->rep;
  rep.ms.database = dbc.ms;
  rep.ms.load = fin.load_ms;
  rep.ms.detect = fin.detect_ms;
  const auto t0 = Clock::now();
  if (!fin.detection_reason.empty() || fin.stars.size() < 3)
    rep.failure = "too few stars " + std::string(fin.star_list ? "listed" : "detected") + " (" +
                  std::to_string(fin.stars.size()) + ")" +
                  (fin.detection_reason.empty() ? "" : ": " + fin.detection_reason);
  else
    rep.ps = identify(o, fin, db, cs, t_start);
  if (rep.failure.empty() && rep.ps.search.result.solved())
    changeFrame(rep.ps.search.result, db, databaseFrame(db.params()), db.params().epoch_jyear,
                frame_, dbc.epoch.jyear);
  rep.ms.identify = msSince(t0);
  rep.ms.total = msSince(t_start) + (dbc.before_frame ? dbc.ms : 0.0);
  if (rep.failure.empty() && !rep.ps.search.result.solved()) rep.failure = rep.ps.search.result.reason;
  f->code = rep.failure.empty() ? kSolved : kNotSolved;
  f->ms = rep.ms.total;
  return f;
}

nlohmann::ordered_json outcomeJson(const FrameOutcome& f) {
  if (!f.rep) {
    nlohmann::ordered_json j = errorJson(f.error, f.code);
    j["image"] = f.o.input;
    return j;
  }
  return f.rep->failure.empty() ? solutionJson(*f.rep) : failureJson(*f.rep);
}

}  // namespace st::solve

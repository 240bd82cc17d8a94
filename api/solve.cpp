// st::api::solve: `startracker solve` on an image in memory. The steps are the command's
// (app/solve/solve_run.cpp): camera or FOV search -> database -> detection -> both parities;
// the JSON is the command's own (app/solve/solve_output.cpp), so the two cannot drift apart.
#include <chrono>
#include <memory>
#include <mutex>

#include "api/database_cache.hpp"
#include "app/image_io.hpp"
#include "app/solve/frame_input.hpp"
#include "app/solve/solve_epoch.hpp"
#include "app/solve/solve_options.hpp"
#include "app/solve/identify_frame.hpp"
#include "app/solve/solve_output.hpp"
#include "include/startracker/startracker.hpp"
#include "sensors/attitude/wahba.hpp"
#include "sensors/detect/star_detector.hpp"
#include "sensors/identify/fov_search.hpp"
#include "sensors/identify/plate_solve.hpp"

namespace st::api {
namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

/// The command's options for these: solve_output reads its fields (image name, solver).
app::SolveOptions commandOptions(const SolveOptions& o) {
  app::SolveOptions c;
  c.input = o.name;
  c.camera.camera_file = o.camera_file;
  c.camera.camera_section = o.camera_section;
  c.camera.fov_deg = o.fov_deg.value_or(0);
  if (o.fov_deg && !(*o.fov_deg > 0 && *o.fov_deg < 180))
    throw InputError("fov_deg " + std::to_string(*o.fov_deg) + ": must be in (0, 180) deg");
  c.fov_range_deg = {o.fov_min_deg, o.fov_max_deg};
  if (!o.algorithm.empty()) c.algorithm = o.algorithm;
  c.solver = o.solver;
  c.mag_limit = o.mag_limit;
  c.epoch = o.epoch_jyear.value_or(0);
  c.max_stars = o.max_stars;
  c.min_sigma_px = o.min_sigma_px.value_or(-1);
  if (o.parity != "normal" && o.parity != "flipped" && o.parity != "both")
    throw InputError("parity '" + o.parity + "': must be normal, flipped or both");
  c.parity = o.parity;
  c.ra_deg = o.ra_deg;
  c.dec_deg = o.dec_deg;
  c.radius_deg = o.radius_deg;
  if (!(o.cpulimit_s >= 0)) throw InputError("cpulimit_s must be >= 0");
  c.cpulimit_s = o.cpulimit_s;
  return c;
}

ParityChoice parityChoice(const std::string& p) {
  if (p == "normal") return ParityChoice::Normal;
  if (p == "flipped") return ParityChoice::Flipped;
  return ParityChoice::Both;
}

/// The hint when all three are given (the command's checks, in the API's names).
std::optional<PositionHint> positionHint(const SolveOptions& o) {
  const int given = int(!std::isnan(o.ra_deg)) + int(!std::isnan(o.dec_deg)) + int(!std::isnan(o.radius_deg));
  if (given == 0) return std::nullopt;
  if (given != 3) throw InputError("ra_deg, dec_deg and radius_deg go together");
  if (!(o.ra_deg >= 0 && o.ra_deg <= 360 && o.dec_deg >= -90 && o.dec_deg <= 90 &&
        o.radius_deg > 0 && o.radius_deg <= 180))
    throw InputError("position hint out of range: ra_deg in [0, 360], dec_deg in [-90, 90], "
                     "radius_deg in (0, 180]");
  return PositionHint{deg2rad(o.ra_deg), deg2rad(o.dec_deg), deg2rad(o.radius_deg)};
}

void requireImage(const cv::Mat& image) {
  if (image.empty()) throw InputError("image: empty");
  if (image.type() != CV_8UC1 && image.type() != CV_16UC1)
    throw InputError("image: type " + std::to_string(image.type()) +
                     " is not 8- or 16-bit single-channel grey (CV_8UC1 / CV_16UC1)");
  if (image.cols < app::kMinImageSide || image.rows < app::kMinImageSide ||
      std::int64_t(image.cols) * image.rows > app::kMaxImagePixels)
    throw InputError("image: " + std::to_string(image.cols) + "x" + std::to_string(image.rows) +
                     " px is outside " + std::to_string(app::kMinImageSide) +
                     " px per side .. 100 Mpx");
}

SolveResult run(app::FrameInput&& in, const SolveOptions& api_o, const Database* db,
                Clock::time_point t_start) {
  const app::SolveOptions o = commandOptions(api_o);
  const std::optional<PositionHint> hint = positionHint(api_o);
  SearchPlan plan = searchPlan(o, in.width, in.height);

  auto t0 = Clock::now();
  const app::SolveEpoch epoch = app::chooseEpoch(
      o.epoch, in.epoch_jyear, in.epoch_source, db && db->fromFile() ? &db->stars() : nullptr);
  const Database chosen = db ? *db : cachedDatabase(plan, o.mag_limit, epoch.jyear);
  if (db && db->fromFile()) app::requireDatabaseEpoch(chosen.stars(), chosen.source(), epoch);
  const double db_ms = msSince(t0);

  if (!in.image.empty()) {
    t0 = Clock::now();
    DetectionResult det = detectStars(in.image);
    in.detect_ms = msSince(t0);
    in.stars = std::move(det.stars);
    in.detection_reason = det.reason;
  }

  // The answer is in the frame of the database the API built (apparent, annual aberration).
  auto rep_ptr = std::make_unique<app::SolveReport>(app::SolveReport{
      o, in, chosen.stars(), chosen.source(), epoch, PlateSolveResult{}, std::string{},
      plan.fit_focal, app::SolveTimings{}, app::databaseFrame(chosen.stars().params())});
  app::SolveReport& rep = *rep_ptr;
  rep.ms.database = db_ms;
  rep.ms.load = in.load_ms;
  rep.ms.detect = in.detect_ms;
  t0 = Clock::now();
  if (!in.detection_reason.empty() || in.stars.size() < 3) {
    rep.failure = "too few stars detected (" + std::to_string(in.stars.size()) + ")" +
                  (in.detection_reason.empty() ? "" : ": " + in.detection_reason);
  } else {
    rep.ps = app::identifyFrame(o, in.stars, in.width, in.height, chosen.stars(),
                                {plan.fixed, plan.fit_focal, plan.grid, plan.scale_tol}, hint,
                                parityChoice(o.parity), t_start, "");
  }
  rep.ms.identify = msSince(t0);
  rep.ms.total = msSince(t_start);
  if (rep.failure.empty() && !rep.ps.search.result.solved())
    rep.failure = rep.ps.search.result.reason;

  SolveResult out;
  out.solved = rep.failure.empty();
  if (!out.solved) {
    out.json = app::failureJson(rep);
    return out;
  }
  out.json = app::solutionJson(rep);
  const IdentifyResult& res = rep.ps.search.result;
  out.q_ib = canonical(res.q_ic);
  out.covariance = res.cov_cam;
  const RaDecRoll rdr = raDecRollFromAttitude(res.q_ic);
  out.ra_deg = rad2deg(rdr.ra);
  out.dec_deg = rad2deg(rdr.dec);
  out.roll_deg = rad2deg(rdr.roll);
  return out;
}

}  // namespace

SolveResult solve(const cv::Mat& image, const SolveOptions& options, const Database* db) {
  const auto t_start = Clock::now();
  requireImage(image);
  app::FrameInput in;
  in.image = image;  // a header on the caller's pixels, no copy
  in.width = image.cols;
  in.height = image.rows;
  return run(std::move(in), options, db, t_start);
}

SolveResult solve(const void* data, int width, int height, int type, std::size_t step_bytes,
                  const SolveOptions& options, const Database* db) {
  if (!data) throw InputError("image: null buffer");
  if (type != CV_8UC1 && type != CV_16UC1)
    throw InputError("image: type " + std::to_string(type) + " is not CV_8UC1 or CV_16UC1");
  if (width <= 0 || height <= 0)
    throw InputError("image: size " + std::to_string(width) + "x" + std::to_string(height));
  // cv::Mat never writes through a header it does not own.
  const cv::Mat m(height, width, type, const_cast<void*>(data),
                  step_bytes ? step_bytes : std::size_t(cv::Mat::AUTO_STEP));
  return solve(m, options, db);
}

SolveResult solveFile(const std::string& path, SolveOptions options, const Database* db) {
  const auto t_start = Clock::now();
  app::LoadedImage img = app::loadImage(path);
  app::FrameInput in;
  in.load_ms = msSince(t_start);
  in.width = img.image.cols;
  in.height = img.image.rows;
  in.epoch_jyear = img.epoch_jyear;
  in.epoch_source = img.epoch_source;
  in.image = std::move(img.image);
  if (options.name == SolveOptions{}.name) options.name = path;
  return run(std::move(in), options, db, t_start);
}

}  // namespace st::api

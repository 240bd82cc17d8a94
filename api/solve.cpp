// st::api::solve: the plate-solving stage (solve/plate_solver.hpp) on an image in memory or a
// file, with the facade's option names. The stage's JSON is the result's, so `startracker
// solve --json`, this and Python's startracker.solve print one object for one frame.
#include <memory>
#include <mutex>

#include "imageio/image_file.hpp"
#include "include/startracker/startracker.hpp"
#include "sensors/identify/star_observation.hpp"
#include "solve/plate_solver.hpp"

namespace st::api {
namespace {

/// The stage's options for these; the library names options without "--".
solve::SolveOptions stageOptions(const SolveOptions& o) {
  solve::SolveOptions c;
  c.option_prefix = "";
  c.camera.camera_file = o.camera_file;
  c.camera.camera_section = o.camera_section;
  if (o.fov_deg && !(*o.fov_deg > 0 && *o.fov_deg < 180))
    throw InputError("fov_deg " + std::to_string(*o.fov_deg) + ": must be in (0, 180) deg");
  c.camera.fov_deg = o.fov_deg.value_or(0);
  if (o.pixel_aspect) {
    if (!(*o.pixel_aspect > 0))
      throw InputError("pixel_aspect " + std::to_string(*o.pixel_aspect) + ": must be > 0");
    c.camera.pixel_aspect = *o.pixel_aspect;
  }
  c.fov_range_deg = {o.fov_min_deg, o.fov_max_deg};
  if (!o.algorithm.empty()) c.algorithm = o.algorithm;
  if (!o.solver.empty()) c.solver = o.solver;
  c.mag_limit = o.mag_limit;
  if (o.epoch_jyear && !(*o.epoch_jyear >= 1000 && *o.epoch_jyear <= 3000))
    throw InputError("epoch_jyear " + std::to_string(*o.epoch_jyear) +
                     ": must be a Julian year in [1000, 3000] (as solve's --epoch)");
  c.epoch = o.epoch_jyear.value_or(0);
  c.max_stars = o.max_stars;
  if (o.min_sigma_px && !(*o.min_sigma_px > 0 && *o.min_sigma_px <= kMaxCentroidSigmaFloorPx))
    throw InputError("min_sigma_px " + std::to_string(*o.min_sigma_px) +
                     ": must be in (0, 2] px (as solve's --min-sigma-px)");
  c.min_sigma_px = o.min_sigma_px.value_or(-1);
  if (o.parity != "normal" && o.parity != "flipped" && o.parity != "both")
    throw InputError("parity '" + o.parity + "': must be normal, flipped or both");
  c.parity = o.parity;
  c.ra_deg = o.ra_deg;
  c.dec_deg = o.dec_deg;
  c.radius_deg = o.radius_deg;
  if (!(o.cpulimit_s >= 0)) throw InputError("cpulimit_s must be >= 0");
  c.cpulimit_s = o.cpulimit_s;
  c.no_aberration = o.no_aberration;
  c.observer_velocity_km_s = o.observer_velocity_km_s;
  c.no_cache = o.no_cache;
  c.width = o.width;
  c.height = o.height;
  return c;
}

solve::PlateSolver solverFor(const SolveOptions& o, const Database* db) {
  if (db) return solve::PlateSolver(stageOptions(o), db->shared(), db->source(), db->fromFile());
  return solve::PlateSolver(stageOptions(o));
}

SolveResult resultOf(const solve::FrameOutcome& f) {
  SolveResult out;
  out.json = solve::outcomeJson(f);
  out.solved = f.code == solve::kSolved;
  if (!out.solved) return out;
  const IdentifyResult& res = f.rep->ps.search.result;
  out.q_ib = canonical(res.q_ic);
  out.covariance = res.cov_cam;
  const RaDecRoll rdr = raDecRollFromAttitude(res.q_ic);
  out.ra_deg = rad2deg(rdr.ra);
  out.dec_deg = rad2deg(rdr.dec);
  out.roll_deg = rad2deg(rdr.roll);
  return out;
}

void requireImage(const cv::Mat& image) {
  if (image.empty()) throw InputError("image: empty");
  if (image.type() != CV_8UC1 && image.type() != CV_16UC1)
    throw InputError("image: type " + std::to_string(image.type()) +
                     " is not 8- or 16-bit single-channel grey (CV_8UC1 / CV_16UC1)");
  imageio::requireImageSize("image", image.cols, image.rows);
}

}  // namespace

SolveResult solve(const cv::Mat& image, const SolveOptions& options, const Database* db) {
  requireImage(image);
  const solve::PlateSolver solver = solverFor(options, db);
  return resultOf(*solver.solveImage(image, options.name));
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
  const solve::PlateSolver solver = solverFor(options, db);
  return resultOf(*solver.solveFile(path));
}

}  // namespace st::api

#include "app/solve/identify_frame.hpp"

#include "common/errors.hpp"
#include "sensors/attitude/wahba.hpp"

namespace st::app {

PlateSolveResult identifyFrame(const SolveOptions& o, const std::vector<Centroid>& stars,
                               int width, int height, const StarDatabase& db,
                               const CameraChoice& cameras,
                               const std::optional<PositionHint>& hint, ParityChoice parity,
                               std::chrono::steady_clock::time_point t_start,
                               const std::string& option_prefix) {
  using Clock = std::chrono::steady_clock;
  IdentifyOptions io;
  io.solver = o.solver;
  io.max_stars = o.max_stars;
  std::string err;
  auto identifier = StarIdentifier::create(o.algorithm, io, &err);
  if (!identifier) throw InputError(option_prefix + "algorithm: " + err);
  if (!WahbaSolver::create(o.solver, &err)) throw InputError(option_prefix + "solver: " + err);
  const double sigma_floor = o.min_sigma_px >= 0 ? o.min_sigma_px : 0.1;
  SearchLimits limits;
  if (hint) limits.refuse = refuseOutsideHint(*hint);
  if (o.cpulimit_s > 0)
    limits.deadline = t_start + std::chrono::duration_cast<Clock::duration>(
                                    std::chrono::duration<double>(o.cpulimit_s));
  const CentroidSearch search = [&](const std::vector<Centroid>& s) {
    // An approximate FOV (no camera file) gets 1 % slack and a focal + distortion fit; a
    // camera file is used as it is and healed when that fails.
    if (cameras.fixed)
      return identifyAndFit(s, *cameras.fixed, db, *identifier,
                            cameras.fit_focal ? CameraFitPolicy::approximateFov(0.01)
                                              : CameraFitPolicy::cameraFile(*cameras.fixed),
                            sigma_floor, limits);
    return identifyUnknownFov(s, width, height, db, *identifier, cameras.grid, cameras.scale_tol,
                              sigma_floor, limits);
  };
  return solveBothParities(stars, width, parity, limits, search);
}

}  // namespace st::app

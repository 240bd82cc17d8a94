#include "solve/identify_frame.hpp"

#include "common/errors.hpp"
#include "sensors/attitude/wahba.hpp"

namespace st::solve {

PlateSolveResult identifyFrame(const SolveOptions& o, const std::vector<Centroid>& stars,
                               int width, int height, const StarDatabase& db,
                               const CameraChoice& cameras,
                               const std::optional<PositionHint>& hint, ParityChoice parity,
                               std::chrono::steady_clock::time_point t_start) {
  const std::string& option_prefix = o.option_prefix;
  using Clock = std::chrono::steady_clock;
  IdentifyOptions io;
  io.solver = o.solver;
  io.max_stars = o.max_stars;
  if (o.cpulimit_s > 0)  // inside each try as well as between them
    io.deadline = t_start + std::chrono::duration_cast<Clock::duration>(
                                std::chrono::duration<double>(o.cpulimit_s));
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
  // An approximate FOV (no camera file) gets 1 % slack and a focal + distortion fit; a
  // camera file is used as it is and healed when that fails.
  LostInSpaceCameras lis;
  lis.camera = cameras.fixed;
  if (cameras.fixed)
    lis.policy = cameras.fit_focal
                     ? CameraFitPolicy::approximateFov(0.01, cameras.fixed->pixelAspect())
                                   : CameraFitPolicy::cameraFile(*cameras.fixed);
  lis.fov_grid = cameras.grid;
  lis.scale_tol = cameras.scale_tol;
  lis.pixel_aspect = cameras.pixel_aspect;
  return lostInSpace(stars, width, height, db, *identifier, lis, sigma_floor, parity, limits);
}

}  // namespace st::solve

#include "sensors/identify/plate_solve.hpp"

#include <cmath>
#include <cstdio>

#include "common/conventions.hpp"

namespace st {

const char* toString(Parity p) { return p == Parity::Normal ? "normal" : "flipped"; }

double boresightDistance(const Quat& q_ic, const PositionHint& hint) {
  const Vec3 boresight_i = q_ic * Vec3::UnitZ();
  const Vec3 centre_i(std::cos(hint.dec) * std::cos(hint.ra),
                      std::cos(hint.dec) * std::sin(hint.ra), std::sin(hint.dec));
  return std::atan2(boresight_i.cross(centre_i).norm(), boresight_i.dot(centre_i));
}

std::function<std::string(const IdentifyResult&)> refuseOutsideHint(const PositionHint& hint) {
  return [hint](const IdentifyResult& r) -> std::string {
    const double d = boresightDistance(r.q_ic, hint);
    if (d <= hint.radius) return "";
    char b[160];
    std::snprintf(b, sizeof b, "solution %.2f deg from the position hint (radius %.2f deg)",
                  rad2deg(d), rad2deg(hint.radius));
    return b;
  };
}

std::vector<Centroid> mirrorLeftRight(const std::vector<Centroid>& centroids, int width) {
  std::vector<Centroid> out = centroids;
  for (Centroid& c : out) {
    c.px.x() = (width - 1) - c.px.x();
    // x -> -x flips the sign of the x-y correlation of the covariance and of the shape.
    c.cov_px(0, 1) = -c.cov_px(0, 1);
    c.cov_px(1, 0) = -c.cov_px(1, 0);
    c.shape(0, 1) = -c.shape(0, 1);
    c.shape(1, 0) = -c.shape(1, 0);
  }
  return out;
}

PlateSolveResult solveBothParities(const std::vector<Centroid>& centroids, int width,
                                   ParityChoice choice, const SearchLimits& limits,
                                   const CentroidSearch& search) {
  PlateSolveResult out;
  std::vector<Parity> order;
  if (choice != ParityChoice::Flipped) order.push_back(Parity::Normal);
  if (choice != ParityChoice::Normal) order.push_back(Parity::Flipped);
  std::string normal_reason;
  for (Parity p : order) {
    if (out.parities_tried > 0 && limits.expired()) {
      out.search.cpu_limit_reached = true;
      out.search.result.reason = kCpuLimitReason;
      break;
    }
    ++out.parities_tried;
    out.parity = p;
    out.search = search(p == Parity::Normal ? centroids : mirrorLeftRight(centroids, width));
    if (out.search.result.solved() || out.search.cpu_limit_reached) break;
    if (p == Parity::Normal) normal_reason = out.search.result.reason;
  }
  if (!out.search.result.solved() && out.parities_tried == 2 && !out.search.cpu_limit_reached)
    out.search.result.reason =
        "normal parity: " + normal_reason + "; flipped parity: " + out.search.result.reason;
  return out;
}

PlateSolveResult lostInSpace(const std::vector<Centroid>& centroids, int width, int height,
                             const StarDatabase& db, StarIdentifier& identifier,
                             const LostInSpaceCameras& cameras, double sigma_floor_px,
                             ParityChoice parity, const SearchLimits& limits) {
  // Never a pattern (nor a verification star) on a radiation hit: detection ranks them after
  // every star, so the stars are the prefix before the first and their indices stay.
  std::size_t n_stars = 0;
  while (n_stars < centroids.size() && !(centroids[n_stars].flags & kRadiationHit)) ++n_stars;
  if (n_stars < centroids.size()) {
    const std::vector<Centroid> stars(centroids.begin(),
                                      centroids.begin() + static_cast<std::ptrdiff_t>(n_stars));
    return lostInSpace(stars, width, height, db, identifier, cameras, sigma_floor_px, parity,
                       limits);
  }
  const CentroidSearch search = [&](const std::vector<Centroid>& s) {
    if (cameras.camera)
      return identifyAndFit(s, *cameras.camera, db, identifier, cameras.policy, sigma_floor_px,
                            limits);
    return identifyUnknownFov(s, width, height, db, identifier, cameras.fov_grid,
                              cameras.scale_tol, sigma_floor_px, limits, cameras.pixel_aspect);
  };
  return solveBothParities(centroids, width, parity, limits, search);
}

}  // namespace st

#include "catalog/database_recipe.hpp"

#include <cstdio>

#include "common/conventions.hpp"
#include "common/errors.hpp"

namespace st {

DatabaseParams databaseParams(const CameraDatabaseRecipe& r) {
  if (!(r.diagonal_fov_rad > 0) || !(r.pixel_scale_rad > 0))
    throw InputError("star database recipe: the camera's field of view and pixel scale must be > 0");
  DatabaseParams p{};
  p.max_pair_angle = r.diagonal_fov_rad + deg2rad(0.2);
  p.mag_limit = r.mag_limit;
  p.epoch_jyear = r.epoch_jyear;
  p.aberration = r.aberration;
  p.parallax = true;
  p.double_star_sep = kUnresolvedDoubleSepPx * r.pixel_scale_rad;  // one image peak
  p.max_stars_per_region = 0;
  p.neighbour_radius = r.diagonal_fov_rad / 2;
  return p;
}

std::string pairCoverageWarning(const DatabaseParams& p, double diagonal_fov_rad,
                                const std::string& db_path) {
  if (p.max_pair_angle >= diagonal_fov_rad * 0.999) return {};
  char b[512];
  std::snprintf(b, sizeof b,
                "%s holds pairs up to %.2f deg, the image diagonal is %.2f deg; stars far apart "
                "will not be paired (rebuild it with `catalog build --diagonal-fov-deg %.2f`, or "
                "--fov-deg H --size W H with the image's horizontal FOV and size)",
                db_path.c_str(), rad2deg(p.max_pair_angle), rad2deg(diagonal_fov_rad),
                rad2deg(diagonal_fov_rad) + 0.01);
  return b;
}

}  // namespace st

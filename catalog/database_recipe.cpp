#include "catalog/database_recipe.hpp"

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
  p.double_star_sep = 1.5 * r.pixel_scale_rad;  // unresolved doubles: one image peak
  p.max_stars_per_region = 0;
  p.neighbour_radius = r.diagonal_fov_rad / 2;
  return p;
}

}  // namespace st

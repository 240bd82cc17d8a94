#include "api/database_cache.hpp"

#include <cstdio>
#include <mutex>

#include "app/solve/solve_epoch.hpp"
#include "catalog/database_recipe.hpp"
#include "catalog/star_catalog.hpp"

namespace st::api {

SearchPlan searchPlan(const app::SolveOptions& o, int w, int h) {
  SearchPlan p;
  if (o.camera.given()) {
    p.fixed = o.camera.resolve(w, h);
    p.fit_focal = o.camera.camera_file.empty();
    p.max_diag = 2 * p.fixed->halfDiagonalFov();
    p.pixel_scale = p.fixed->pixelScale();
    return p;
  }
  if (o.fov_range_deg.size() != 2 || o.fov_range_deg[0] <= 0 ||
      o.fov_range_deg[1] < o.fov_range_deg[0])
    throw InputError("fov_min_deg, fov_max_deg: need 0 < MIN <= MAX in degrees");
  p.grid = fovSearchGrid(deg2rad(o.fov_range_deg[0]), deg2rad(o.fov_range_deg[1]), p.scale_tol);
  p.max_diag = 2 * CameraModel::fromFov(w, h, p.grid.back()).halfDiagonalFov() * (1 + p.scale_tol);
  p.pixel_scale = CameraModel::fromFov(w, h, p.grid.front()).pixelScale();
  return p;
}

namespace {

struct CacheEntry {
  double max_diag = 0, pixel_scale = 0, mag_limit = 0;
  std::optional<Database> db;
};

}  // namespace

Database buildDatabase(double max_diag, double pixel_scale, double mag_limit, double epoch_jyear) {
  CameraDatabaseRecipe r;
  r.diagonal_fov_rad = max_diag;
  r.pixel_scale_rad = pixel_scale;
  r.mag_limit = mag_limit;
  r.epoch_jyear = epoch_jyear;
  r.aberration = true;
  const std::string cat = StarDatabase::defaultCatalogPath();
  auto db = std::make_shared<const StarDatabase>(StarDatabase::build(loadCatalog(cat), databaseParams(r)));
  char b[400];
  std::snprintf(b, sizeof b, "built in memory from %s (V <= %.1f)", cat.c_str(), mag_limit);
  return Database(std::move(db), b, false);
}

Database cachedDatabase(const SearchPlan& plan, double mag_limit, double epoch_jyear) {
  static std::mutex mutex;
  static CacheEntry last;
  std::lock_guard<std::mutex> lock(mutex);
  if (last.db && last.max_diag == plan.max_diag && last.pixel_scale == plan.pixel_scale &&
      last.mag_limit == mag_limit &&
      app::epochShiftBoundArcsec(last.db->stars().params(), epoch_jyear) <= app::kEpochToleranceArcsec)
    return *last.db;
  last = {plan.max_diag, plan.pixel_scale, mag_limit,
          buildDatabase(plan.max_diag, plan.pixel_scale, mag_limit, epoch_jyear)};
  return *last.db;
}

}  // namespace st::api

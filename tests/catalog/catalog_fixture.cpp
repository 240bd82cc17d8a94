#include "tests/catalog/catalog_fixture.hpp"

#include "common/conventions.hpp"

namespace st::test {

const StarCatalog& hipSubset() {
  static const StarCatalog cat = loadHipparcos(StarDatabase::defaultCatalogPath());
  return cat;
}

DatabaseParams params15() {
  DatabaseParams p{};
  p.max_pair_angle = deg2rad(15.0);
  p.mag_limit = 6.5;
  p.epoch_jyear = 2020.0;
  p.aberration = true;
  p.double_star_sep = arcsec2rad(10.0);
  p.max_stars_per_region = 0;
  p.neighbour_radius = deg2rad(5.0);
  return p;
}

const StarDatabase& hipDatabase15() {
  static const StarDatabase db = StarDatabase::build(hipSubset(), params15());
  return db;
}

}  // namespace st::test

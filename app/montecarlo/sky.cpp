#include "app/montecarlo/sky.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "catalog/star_catalog.hpp"
#include "common/conventions.hpp"
#include "common/log.hpp"

namespace st::app::mc {

std::shared_ptr<const StarDatabase> buildDatabase(const McOptions& o, double max_pair_angle,
                                                  double mag_limit) {
  const std::string path = o.catalog.empty() ? StarDatabase::defaultCatalogPath() : o.catalog;
  const StarCatalog cat = loadCatalog(path);
  DatabaseParams p{};
  p.max_pair_angle = max_pair_angle;
  p.mag_limit = mag_limit;
  p.epoch_jyear = 2000.0;
  p.aberration = false;
  p.parallax = false;
  p.double_star_sep = arcsec2rad(o.merge_arcsec);
  p.max_stars_per_region = 0;
  p.neighbour_radius = max_pair_angle / 2;  // as `solve`: Liebe's features need the neighbours
  auto db = std::make_shared<StarDatabase>(StarDatabase::build(cat, p));
  if (o.progress)
    log::info("database: %zu stars V <= %.2f, %zu pairs <= %.2f deg (%.2f s)", db->stars().size(),
              mag_limit, db->pairs().size(), rad2deg(max_pair_angle), db->report().build_seconds);
  return db;
}

CameraModel makeCamera(const McOptions& o) {
  return CameraModel::fromFov(o.width, o.height, deg2rad(o.fov_deg));
}

Quat randomAttitude(std::mt19937_64& rng) {
  std::normal_distribution<double> n01;
  Quat q(n01(rng), n01(rng), n01(rng), n01(rng));
  q.normalize();
  return canonical(q);
}

double fieldStop(const McOptions& o) { return deg2rad(o.field_stop_deg); }

std::vector<VisibleStar> visibleStars(const StarDatabase& db, const CameraModel& cam,
                                      const Quat& q_ib, double mag_limit, double field_stop_rad) {
  std::vector<uint32_t> cone;
  const Mat3 R_ib = q_ib.toRotationMatrix();
  const double radius = field_stop_rad > 0 ? std::min(cam.halfDiagonalFov(), field_stop_rad / 2)
                                           : cam.halfDiagonalFov();
  db.coneQuery(R_ib.col(2), radius, cone);
  std::vector<VisibleStar> out;
  for (uint32_t s : cone) {
    const Star& star = db.stars()[s];
    if (star.mag > mag_limit) continue;
    const auto px = cam.vectorToPixel(R_ib.transpose() * star.u_i);
    if (!px || !cam.isPixelInImage(*px)) continue;
    out.push_back({s, *px, star.mag});
  }
  return out;  // cone results are ascending index = brightest first
}

Scene makeScene(std::mt19937_64& rng, const CameraModel& cam,
                const std::vector<VisibleStar>& visible, const ErrorSituation& sit) {
  std::normal_distribution<double> n01;
  std::uniform_real_distribution<double> u01;
  struct Item {
    double mag;
    Centroid c;
    int truth;
  };
  std::vector<Item> items;
  const Mat2 cov = sit.noise_px * sit.noise_px * Mat2::Identity();
  auto centroid = [&](const Vec2& px, double mag) {
    Centroid c{};
    c.px = px;
    c.cov_px = cov;
    c.flux = 1e6 * std::pow(10.0, -0.4 * mag);
    c.peak = c.flux / 10;
    c.snr = 100;
    c.area = 9;
    c.flags = 0;
    return c;
  };
  for (const VisibleStar& v : visible) {
    if (sit.drop_fraction > 0 && u01(rng) < sit.drop_fraction) continue;
    const Vec2 px = v.px + sit.noise_px * Vec2(n01(rng), n01(rng));
    items.push_back({v.mag, centroid(px, v.mag), static_cast<int>(v.star)});
  }
  // Exactly `missing` more true stars gone (seed 003 "1 star missing").
  for (int m = 0; m < sit.missing && !items.empty(); ++m)
    items.erase(items.begin() +
                std::uniform_int_distribution<long>(0, long(items.size()) - 1)(rng));
  // Displaced stars: a random direction, displace_sigma sigmas away (seed 003 "outside the
  // tolerance limits"), reported with the nominal covariance.
  std::vector<std::size_t> order(items.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  const int n_disp = std::min<int>(sit.displaced, static_cast<int>(items.size()));
  for (int d = 0; d < n_disp; ++d) {
    const long pick = std::uniform_int_distribution<long>(d, long(order.size()) - 1)(rng);
    std::swap(order[d], order[pick]);
    const double a = kTwoPi * u01(rng);
    items[order[d]].c.px += sit.displace_sigma * sit.noise_px * Vec2(std::cos(a), std::sin(a));
  }
  Scene sc;
  sc.n_true = static_cast<int>(items.size());
  for (int f = 0; f < sit.false_stars; ++f) {
    const Vec2 px(u01(rng) * (cam.width() - 1), u01(rng) * (cam.height() - 1));
    const double mag = -1.0 + 7.5 * u01(rng);  // anywhere in the brightness order
    items.push_back({mag, centroid(px, mag), -1});
  }
  sc.n_false = sit.false_stars;
  std::stable_sort(items.begin(), items.end(),
                   [](const Item& a, const Item& b) { return a.mag < b.mag; });
  for (const Item& it : items) {
    sc.centroids.push_back(it.c);
    sc.truth.push_back(it.truth);
  }
  return sc;
}

}  // namespace st::app::mc

/// @file scene.hpp
/// Simulated centroids for identification tests: catalog stars of the database projected
/// with a camera at a known attitude, Gaussian pixel noise, false stars ("spikes") at random
/// positions and brightness ranks, and randomly dropped stars. Fixed seeds in every test.
#pragma once
#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "catalog/star_catalog.hpp"
#include "catalog/star_database.hpp"
#include "sensors/camera/camera_model.hpp"
#include "sensors/detect/centroid.hpp"
#include "tests/support/test_paths.hpp"

namespace st::test {

struct Scene {
  Quat q_ib;
  std::vector<Centroid> centroids;  ///< brightest first
  std::vector<int> truth;           ///< star index per centroid, -1 for a false star
};

inline Quat randomAttitude(std::mt19937_64& rng) {
  std::normal_distribution<double> n01;
  Quat q(n01(rng), n01(rng), n01(rng), n01(rng));
  q.normalize();
  return canonical(q);
}

struct SceneParams {
  double noise_px = 0.1;
  int false_min = 0, false_max = 3;
  double drop_fraction = 0.1;
  double mag_limit = 6.0;
  double claimed_noise_px = -1;  ///< centroid covariance reported (< 0: the true noise_px)
  int displaced = 0;             ///< true stars moved by displace_sigma * noise_px (random
  double displace_sigma = 10.0;  ///< direction) without telling the covariance (seed 003)
};

inline Scene makeScene(std::mt19937_64& rng, const StarDatabase& db, const CameraModel& cam,
                       const SceneParams& p, const Quat& q_ib) {
  Scene sc;
  sc.q_ib = q_ib;
  std::normal_distribution<double> n01;
  std::uniform_real_distribution<double> u01;
  const Mat3 r_bi = q_ib.toRotationMatrix().transpose();
  std::vector<uint32_t> cone;
  db.coneQuery(q_ib.toRotationMatrix().col(2), cam.halfDiagonalFov(), cone);
  struct Item { double mag; Centroid c; int truth; };
  std::vector<Item> items;
  for (uint32_t s : cone) {
    const Star& star = db.stars()[s];
    if (star.mag > p.mag_limit) continue;
    const auto px = cam.vectorToPixel(r_bi * star.u_i);
    if (!px || !cam.isPixelInImage(*px)) continue;
    if (u01(rng) < p.drop_fraction) continue;
    Centroid c;
    c.px = *px + p.noise_px * Vec2(n01(rng), n01(rng));
    const double claimed = p.claimed_noise_px >= 0 ? p.claimed_noise_px : p.noise_px;
    c.cov_px = claimed * claimed * Mat2::Identity();
    c.flux = 1e6 * std::pow(10.0, -0.4 * star.mag);
    items.push_back({star.mag, c, static_cast<int>(s)});
  }
  if (p.displaced > 0) {
    std::vector<std::size_t> order(items.size());
    for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
    std::shuffle(order.begin(), order.end(), rng);
    for (int d = 0; d < std::min<int>(p.displaced, static_cast<int>(order.size())); ++d) {
      const double a = 2 * 3.14159265358979 * u01(rng);
      items[order[d]].c.px += p.displace_sigma * p.noise_px * Vec2(std::cos(a), std::sin(a));
    }
  }
  const int n_false = std::uniform_int_distribution<int>(p.false_min, p.false_max)(rng);
  for (int f = 0; f < n_false; ++f) {
    Centroid c;
    c.px = Vec2(u01(rng) * (cam.width() - 1), u01(rng) * (cam.height() - 1));
    c.cov_px = p.noise_px * p.noise_px * Mat2::Identity();
    const double mag = -1.0 + 7.0 * u01(rng);  // anywhere in the brightness order
    c.flux = 1e6 * std::pow(10.0, -0.4 * mag);
    items.push_back({mag, c, -1});
  }
  std::sort(items.begin(), items.end(),
            [](const Item& a, const Item& b) { return a.mag < b.mag; });
  for (const Item& it : items) {
    sc.centroids.push_back(it.c);
    sc.truth.push_back(it.truth);
  }
  return sc;
}

/// The statistical-test database: committed Hipparcos subset, V <= 6.0, pairs up to the
/// diagonal of a 15 deg camera, epoch 2000.
inline const StarDatabase& testDatabase() {
  static const StarDatabase db = [] {
    const StarCatalog cat = loadCatalog(hipparcosSubsetPath());
    DatabaseParams prm{};
    prm.max_pair_angle = 22.0 * 3.14159265358979 / 180.0;
    prm.mag_limit = 6.0;
    prm.epoch_jyear = 2000.0;
    prm.aberration = false;
    prm.parallax = false;
    prm.double_star_sep = 60.0 / 206264.806;  // ~1.2 px: unresolved on the image
    prm.max_stars_per_region = 0;
    prm.neighbour_radius = 8.0 * 3.14159265358979 / 180.0;
    return StarDatabase::build(cat, prm);
  }();
  return db;
}

inline CameraModel testCamera(double hfov_deg = 15.0) {
  return CameraModel::fromFov(1024, 1024, hfov_deg * 3.14159265358979 / 180.0);
}

}  // namespace st::test

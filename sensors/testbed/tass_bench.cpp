#include "sensors/testbed/tass_bench.hpp"

#include "common/conventions.hpp"

namespace st::testbed {

CameraModel TassBench::camera() const {
  return CameraModel::fromFov(camera_width_px, camera_height_px, deg2rad(camera_hfov_deg));
}

std::vector<Vec2> TassBench::starPixels() const {
  std::mt19937_64 rng(pattern_seed);
  const double w = display.screen_width_px, h = display.screen_height_px;
  std::uniform_real_distribution<double> ux(0.5 * (1 - pattern_extent) * w,
                                            0.5 * (1 + pattern_extent) * w);
  std::uniform_real_distribution<double> uy(0.5 * (1 - pattern_extent) * h,
                                            0.5 * (1 + pattern_extent) * h);
  std::vector<Vec2> px;
  for (int tries = 0; static_cast<int>(px.size()) < star_count && tries < 100000; ++tries) {
    const Vec2 p(std::round(ux(rng)), std::round(uy(rng)));  // drawn at whole screen pixels
    bool ok = true;
    for (const Vec2& q : px)
      ok &= (display.screenPoint(p) - display.screenPoint(q)).norm() >= min_separation_m;
    if (ok) px.push_back(p);
  }
  return px;
}

std::vector<Vec3> TassBench::measure(const std::vector<Vec2>& stars_px, const Quat& q_ib,
                                     std::mt19937_64& rng) const {
  const CameraModel cam = camera();
  std::normal_distribution<double> n01;
  std::vector<Vec3> b;
  for (const Vec2& s : stars_px) {
    const auto px = cam.vectorToPixel(display.cameraVector(display.screenPoint(s), q_ib));
    const Vec2 noise(n01(rng), n01(rng));  // drawn for every star: streams stay aligned
    if (!px || !cam.isPixelInImage(*px)) continue;
    b.push_back(cam.pixelToVector(*px + centroid_noise_px * noise));
  }
  return b;
}

Quat predictionWithError(const Quat& q_true, double error_deg) {
  const double e = deg2rad(error_deg);
  return canonical(q_true * quatFromYpr(Vec3(e, e, e)));
}

}  // namespace st::testbed

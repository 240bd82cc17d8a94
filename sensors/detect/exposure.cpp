#include "sensors/detect/exposure.hpp"

#include <algorithm>
#include <cmath>

#include "common/check.hpp"

namespace st {

double maxImageSpeedPxPerS(const CameraModel& cam, const Vec3& omega_cam) {
  const double w = omega_cam.norm();
  if (!(w > 0)) return 0.0;
  // A small turn (1e-4 rad): the image motion field is linear in it to ~1e-4 relative.
  const double dt = 1e-4 / w;
  const Mat3 R = quatExp(omega_cam * dt).toRotationMatrix();
  double fastest = 0;
  constexpr int kGrid = 9;
  for (int iy = 0; iy < kGrid; ++iy)
    for (int ix = 0; ix < kGrid; ++ix) {
      const Vec2 p(ix * (cam.width() - 1.0) / (kGrid - 1), iy * (cam.height() - 1.0) / (kGrid - 1));
      const Vec3 v = cam.pixelToVector(p);
      // A fixed star seen from a camera turned by R: the direction R^T v.
      const auto q = cam.vectorToPixel(R.transpose() * v);
      if (q) fastest = std::max(fastest, (*q - p).norm() / dt);
    }
  return fastest;
}

double exposureForRate(const CameraModel& cam, const Vec3& omega_cam, double max_smear_px,
                       double min_s, double max_s) {
  ST_ASSERT(max_smear_px > 0 && min_s > 0 && min_s <= max_s);
  const double speed = maxImageSpeedPxPerS(cam, omega_cam);
  if (!(speed > 0)) return max_s;
  return std::clamp(max_smear_px / speed, min_s, max_s);
}

}  // namespace st

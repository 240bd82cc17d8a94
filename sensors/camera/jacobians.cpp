#include "sensors/camera/jacobians.hpp"

namespace st {

Mat23 projectionJacobian(const CameraModel& cam, const Vec3& v) {
  // Pixel Jacobian of the normalised coordinates times d(x/z, y/z)/dv.
  Mat23 n;
  const double iz = 1.0 / v.z();
  n << iz, 0, -v.x() * iz * iz, 0, iz, -v.y() * iz * iz;
  return cam.pixelJacobian(v) * n;
}

Mat23 attitudeJacobian(const CameraModel& cam, const Vec3& v) {
  return projectionJacobian(cam, v) * skew(v);
}

}  // namespace st

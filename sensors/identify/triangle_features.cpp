#include "sensors/identify/triangle_features.hpp"

#include <algorithm>
#include <cmath>

#include "common/attitude.hpp"

namespace st {

TriangleFeature planarTriangle(const Vec3& b1, const Vec3& b2, const Vec3& b3) {
  const double a = (b1 - b2).norm(), b = (b2 - b3).norm(), c = (b1 - b3).norm();  // eq. 4-6
  const double s = 0.5 * (a + b + c);                                              // eq. 3
  TriangleFeature f;
  f.area = std::sqrt(std::max(0.0, s * (s - a) * (s - b) * (s - c)));              // eq. 2
  f.polar_moment = f.area * (a * a + b * b + c * c) / 36.0;                        // eq. 7
  return f;
}

namespace {

// L'Huilier's theorem, seed 001 eq. 8 with the arcs of eq. 9-11.
double sphericalArea(const Vec3& b1, const Vec3& b2, const Vec3& b3) {
  const double a = angleBetween(b1, b2), b = angleBetween(b2, b3), c = angleBetween(b3, b1);
  const double s = 0.5 * (a + b + c);
  const double t = std::tan(s / 2) * std::tan((s - a) / 2) * std::tan((s - b) / 2) *
                   std::tan((s - c) / 2);
  return 4.0 * std::atan(std::sqrt(std::max(0.0, t)));
}

// Seed 001 eq. 12: I_p = sum theta^2 dA over sub-triangles, theta the arc from each
// sub-triangle's centroid to the centroid of the whole triangle.
double polarMoment(const Vec3& b1, const Vec3& b2, const Vec3& b3, const Vec3& centre,
                   int depth) {
  if (depth == 0) {
    const Vec3 c = (b1 + b2 + b3).normalized();
    const double th = angleBetween(c, centre);
    return th * th * sphericalArea(b1, b2, b3);
  }
  const Vec3 m12 = (b1 + b2).normalized(), m23 = (b2 + b3).normalized(),
             m31 = (b3 + b1).normalized();
  return polarMoment(b1, m12, m31, centre, depth - 1) +
         polarMoment(m12, b2, m23, centre, depth - 1) +
         polarMoment(m31, m23, b3, centre, depth - 1) +
         polarMoment(m12, m23, m31, centre, depth - 1);
}
}  // namespace

TriangleFeature sphericalTriangle(const Vec3& b1, const Vec3& b2, const Vec3& b3, int depth) {
  TriangleFeature f;
  f.area = sphericalArea(b1, b2, b3);
  f.polar_moment = polarMoment(b1, b2, b3, (b1 + b2 + b3).normalized(), depth);
  return f;
}

}  // namespace st

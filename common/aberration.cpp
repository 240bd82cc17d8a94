#include "common/aberration.hpp"

#include <cmath>

#include "common/conventions.hpp"

namespace st {

Vec3 applyAberration(const Vec3& u, const Vec3& velocity_km_s) {
  const Vec3 beta = velocity_km_s / kSpeedOfLightKmS;
  const double b2 = beta.squaredNorm();
  const double inv_gamma = std::sqrt(1.0 - b2);
  const double ub = u.dot(beta);
  return ((inv_gamma * u + (1.0 + ub / (1.0 + inv_gamma)) * beta) / (1.0 + ub)).normalized();
}

}  // namespace st

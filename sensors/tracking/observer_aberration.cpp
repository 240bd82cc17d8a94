#include "sensors/tracking/observer_aberration.hpp"

#include <Eigen/LU>

namespace st {

Quat correctForAberration(const Quat& q_ic, const std::vector<Vec3>& u_i,
                          const std::vector<double>& w, const Vec3& velocity_km_s) {
  Mat3 info = Mat3::Zero();
  Vec3 rhs = Vec3::Zero();
  for (std::size_t k = 0; k < u_i.size() && k < w.size(); ++k) {
    const Vec3& u = u_i[k];
    const Vec3 d = applyAberration(u, velocity_km_s) - u;
    info += w[k] * (Mat3::Identity() - u * u.transpose());
    rhs += w[k] * d.cross(u);
  }
  const Eigen::FullPivLU<Mat3> lu(info);
  if (!lu.isInvertible()) return q_ic;
  const Vec3 phi = lu.solve(rhs);  // u ~ Exp(phi) f(u): R_E
  return canonical(quatExp(phi).conjugate() * q_ic);
}

}  // namespace st

#include "solve/celestial_frame.hpp"

#include <Eigen/SVD>
#include <cmath>
#include <cstdio>

#include "solve/solve_options.hpp"
#include "catalog/epoch_correction.hpp"
#include "common/errors.hpp"

namespace st::solve {

namespace {
constexpr double kLightKmS = 299792.458;
}

Vec3 CelestialFrame::velocity(double epoch_jyear) const {
  Vec3 v = observer_km_s;
  if (annual) v += earthBarycentricState(epoch_jyear).velocity_km_s;
  return v;
}

std::string CelestialFrame::describe(double epoch_jyear) const {
  if (!apparent()) return "astrometric (ICRS catalog directions, no aberration)";
  char b[256];
  std::string s = "apparent:";
  if (annual) {
    std::snprintf(b, sizeof b, " annual aberration at %.3f", epoch_jyear);
    s += b;
  }
  if (observer_km_s.squaredNorm() > 0) {
    std::snprintf(b, sizeof b, "%s observer velocity (%.3f, %.3f, %.3f) km/s", annual ? " +" : "",
                  observer_km_s.x(), observer_km_s.y(), observer_km_s.z());
    s += b;
  }
  return s;
}

CelestialFrame requestedFrame(const SolveOptions& o) {
  CelestialFrame f;
  f.annual = !o.no_aberration;
  if (o.observer_velocity_km_s.empty()) return f;
  if (o.no_aberration)
    throw InputError("--observer-velocity-km-s with --no-aberration: the astrometric frame has "
                     "no aberration to add a velocity to");
  f.observer_km_s = Vec3(o.observer_velocity_km_s[0], o.observer_velocity_km_s[1],
                         o.observer_velocity_km_s[2]);
  if (!f.observer_km_s.allFinite() || !(f.observer_km_s.norm() < kLightKmS))
    throw InputError("--observer-velocity-km-s: the velocity must be finite and below the speed "
                     "of light (299792 km/s)");
  return f;
}

CelestialFrame databaseFrame(const DatabaseParams& p) {
  CelestialFrame f;
  f.annual = p.aberration;
  return f;
}

void changeFrame(IdentifyResult& res, const StarDatabase& db, const CelestialFrame& from,
                 double from_jyear, const CelestialFrame& to, double to_jyear) {
  const Vec3 v_from = from.velocity(from_jyear);
  const Vec3 v_to = to.velocity(to_jyear);
  if (v_from == v_to || res.matches.empty()) return;
  // Wahba between the star vectors in both frames (equal weights): B = sum u_to u_from^T.
  Mat3 B = Mat3::Zero();
  for (const StarMatch& m : res.matches) {
    const Vec3& u = db.stars()[m.star_index].u_i;
    const Vec3 u_to = applyAberration(applyAberration(u, -v_from), v_to);
    B += u_to * u.transpose();
  }
  Eigen::JacobiSVD<Mat3> svd(B, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Mat3 d = Mat3::Identity();
  d(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant() < 0 ? -1 : 1;
  const Mat3 r = svd.matrixU() * d * svd.matrixV().transpose();  // u_to = r u_from
  // v_i = R(q_ic) v_cam in the database frame, so in the new one R(q) = r R(q_ic).
  res.q_ic = (Quat(r) * res.q_ic).normalized();
}

}  // namespace st::solve

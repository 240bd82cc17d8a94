#include "common/attitude.hpp"

#include <cmath>

#include "common/conventions.hpp"

namespace st {

Quat canonical(const Quat& q) {
  Quat n = q.normalized();
  if (n.w() < 0) n.coeffs() *= -1.0;
  return n;
}

Mat3 skew(const Vec3& v) {
  Mat3 m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}

Quat quatExp(const Vec3& rotvec) {
  const double angle = rotvec.norm();
  const double half = 0.5 * angle;
  // sin(x/2)/x by its series below 1e-4 rad: keeps full precision for tiny rotations.
  const double k = angle < 1e-4 ? 0.5 - angle * angle / 48.0 : std::sin(half) / angle;
  return Quat(std::cos(half), k * rotvec.x(), k * rotvec.y(), k * rotvec.z());
}

Vec3 quatLog(const Quat& q_in) {
  const Quat q = canonical(q_in);
  const Vec3 v = q.vec();
  const double s = v.norm();
  const double angle = 2.0 * std::atan2(s, q.w());
  // angle/sin(angle/2) -> 2 as s -> 0; atan2 keeps it accurate near pi too.
  const double k = s < 1e-12 ? 2.0 / q.w() : angle / s;
  return k * v;
}

Vec3 unitVectorFromRaDec(double ra, double dec) {
  const double cd = std::cos(dec);
  return Vec3(cd * std::cos(ra), cd * std::sin(ra), std::sin(dec));
}

void raDecFromVector(const Vec3& v, double& ra, double& dec) {
  ra = std::atan2(v.y(), v.x());
  if (ra < 0) ra += kTwoPi;
  dec = std::atan2(v.z(), std::hypot(v.x(), v.y()));
}

namespace {
/// [-east | -north | boresight] at (ra, dec): the roll-zero camera axes in inertial.
Mat3 rollZeroFrame(double ra, double dec) {
  const Vec3 b = unitVectorFromRaDec(ra, dec);
  const Vec3 east(-std::sin(ra), std::cos(ra), 0.0);
  const Vec3 north(-std::sin(dec) * std::cos(ra), -std::sin(dec) * std::sin(ra), std::cos(dec));
  Mat3 m;
  m.col(0) = -east;
  m.col(1) = -north;
  m.col(2) = b;
  return m;
}
}  // namespace

Quat attitudeFromRaDecRoll(const RaDecRoll& rdr) {
  const Mat3 R_ib = rollZeroFrame(rdr.ra, rdr.dec) *
                    Eigen::AngleAxisd(rdr.roll, Vec3::UnitZ()).toRotationMatrix();
  return canonical(Quat(R_ib));
}

RaDecRoll raDecRollFromAttitude(const Quat& q_ib) {
  const Mat3 R_ib = q_ib.normalized().toRotationMatrix();
  RaDecRoll out;
  raDecFromVector(R_ib.col(2), out.ra, out.dec);
  const Mat3 Rz = rollZeroFrame(out.ra, out.dec).transpose() * R_ib;
  out.roll = std::atan2(Rz(1, 0), Rz(0, 0));
  return out;
}

AttitudeError attitudeError(const Quat& q_ib_est, const Quat& q_ib_true) {
  const Quat q_err = canonical(q_ib_est.conjugate() * q_ib_true);
  AttitudeError e;
  e.rotvec_body = quatLog(q_err);
  e.total = e.rotvec_body.norm();
  // Swing-twist about +z: twist = (w, 0, 0, z) normalised; swing angle = boresight angle.
  const double twist_norm = std::hypot(q_err.w(), q_err.z());
  if (twist_norm < 1e-15) {  // a half-turn about an axis perpendicular to z: twist undefined
    e.roll = 0;
    e.cross_boresight = e.total;
    return e;
  }
  e.roll = 2.0 * std::atan2(q_err.z(), q_err.w());
  if (e.roll > kPi) e.roll -= kTwoPi;
  if (e.roll <= -kPi) e.roll += kTwoPi;
  // The swing quaternion q_err * twist^-1 has w = twist_norm and |vec| = hypot(x, y);
  // atan2 keeps full precision for tiny angles where acos would not.
  e.cross_boresight = 2.0 * std::atan2(std::hypot(q_err.x(), q_err.y()), twist_norm);
  return e;
}

double attitudeNees(const Quat& q_ib_est, const Mat3& cov_body, const Quat& q_ib_true) {
  const Vec3 e = attitudeError(q_ib_est, q_ib_true).rotvec_body;
  return e.dot(cov_body.ldlt().solve(e));
}

AttitudeSigma attitudeSigma(const Mat3& cov_body) {
  return {std::sqrt(cov_body(0, 0) + cov_body(1, 1)), std::sqrt(cov_body(2, 2))};
}

}  // namespace st

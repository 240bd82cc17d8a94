#include "sensors/testbed/display_geometry.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace st::testbed {

namespace {
std::string geometryProblem(const DisplayGeometry& g) {
  auto positive = [](double v) { return std::isfinite(v) && v > 0; };
  if (!positive(g.screen_distance_m)) return "screen distance must be > 0 m";
  if (!g.lever_arm_m.allFinite()) return "lever arm must be finite";
  if (!g.screen_centre_m.allFinite()) return "screen centre must be finite";
  // The camera must stay below the screen at every attitude: |R_0| < h.
  if (!(g.lever_arm_m.norm() < g.screen_distance_m))
    return "lever arm (|R_0| = " + std::to_string(g.lever_arm_m.norm()) +
           " m) must be shorter than the screen distance (" +
           std::to_string(g.screen_distance_m) + " m)";
  if (g.screen_width_px < 1 || g.screen_height_px < 1) return "screen size in pixels must be >= 1";
  if (!positive(g.screen_width_m) || !positive(g.screen_height_m))
    return "screen size in metres must be > 0";
  return {};
}
}  // namespace

bool DisplayGeometry::isValid(std::string* why) const {
  const std::string p = geometryProblem(*this);
  if (why) *why = p;
  return p.empty();
}

Vec3 DisplayGeometry::screenPoint(const Vec2& px) const {
  return Vec3(screen_centre_m.x() + (px.x() - 0.5 * (screen_width_px - 1)) * pitchX(),
              screen_centre_m.y() + (px.y() - 0.5 * (screen_height_px - 1)) * pitchY(),
              screen_distance_m);
}

Vec2 DisplayGeometry::screenPixel(const Vec3& p) const {
  return Vec2((p.x() - screen_centre_m.x()) / pitchX() + 0.5 * (screen_width_px - 1),
              (p.y() - screen_centre_m.y()) / pitchY() + 0.5 * (screen_height_px - 1));
}

bool DisplayGeometry::isOnScreen(const Vec2& px) const {
  return px.x() >= -0.5 && px.y() >= -0.5 && px.x() <= screen_width_px - 0.5 &&
         px.y() <= screen_height_px - 0.5;
}

Vec3 DisplayGeometry::cameraCentre(const Quat& q_ib) const { return q_ib * lever_arm_m; }

Vec3 DisplayGeometry::cameraVector(const Vec3& point_I, const Quat& q_ib) const {
  return q_ib.conjugate() * (point_I - cameraCentre(q_ib)).normalized();  // seed 001 eq. 53/54
}

std::optional<double> DisplayGeometry::alpha(const Vec3& b_B, const Quat& q_ib) const {
  // seed 001 eq. 56: alpha = (h - p^T A^T R_0) / (p^T A^T b), p = +z here (the screen normal).
  const double denom = (q_ib * b_B).z();
  const double num = screen_distance_m - cameraCentre(q_ib).z();
  if (!(denom > 1e-9)) return std::nullopt;  // ray parallel to the screen or pointing away
  return num / denom;
}

std::optional<Vec3> DisplayGeometry::screenPointFromCamera(const Vec3& b_B,
                                                           const Quat& q_ib) const {
  const auto a = alpha(b_B, q_ib);
  if (!a) return std::nullopt;
  return q_ib * (lever_arm_m + *a * b_B);
}

std::optional<Vec3> DisplayGeometry::nearFieldVector(const Vec3& b_B, const Quat& q_ib_pred) const {
  const auto a = alpha(b_B, q_ib_pred);
  if (!a) return std::nullopt;
  return (lever_arm_m + *a * b_B).normalized();  // seed 001 eq. 54 / beta_i: = A r_i
}

double DisplayGeometry::beta(const Vec3& r_I) const {
  return screen_distance_m / r_I.z();  // seed 001 eq. 57
}

std::optional<Vec3> DisplayGeometry::databaseFromZeroAttitude(const Vec3& b_B) const {
  const auto a = alpha(b_B, Quat::Identity());
  if (!a) return std::nullopt;
  const Vec3 w = lever_arm_m + *a * b_B;  // beta_i r_i (eq. 53 at A = I)
  return w / beta(w.normalized());        // seed 001 eq. 58
}

Quat quatFromYpr(const Vec3& ypr) {
  return Quat(Eigen::AngleAxisd(ypr.x(), Vec3::UnitZ()) *
              Eigen::AngleAxisd(ypr.y(), Vec3::UnitY()) *
              Eigen::AngleAxisd(ypr.z(), Vec3::UnitX()));
}

Vec3 yprFromQuat(const Quat& q) {
  const Mat3 R = q.normalized().toRotationMatrix();
  const double pitch = std::asin(std::clamp(-R(2, 0), -1.0, 1.0));
  return Vec3(std::atan2(R(1, 0), R(0, 0)), pitch, std::atan2(R(2, 1), R(2, 2)));
}

}  // namespace st::testbed

/// @file mrpt_convert.hpp
/// The only place where attitudes cross between Eigen and MRPT types (header-only; users
/// link mrpt::poses). MRPT CQuaternion stores (w, x, y, z) with [0] = w; Eigen's coeffs()
/// are (x, y, z, w): always go through these functions, never Map one onto the other.
#pragma once
#include <mrpt/core/Clock.h>
#include <mrpt/math/CQuaternion.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/poses/CPose3DQuat.h>

#include <chrono>
#include <cmath>

#include "common/attitude.hpp"
#include "common/conventions.hpp"

namespace st {

inline mrpt::math::CQuaternionDouble toMrpt(const Quat& q) {
  const Quat c = canonical(q);
  return mrpt::math::CQuaternionDouble(c.w(), c.x(), c.y(), c.z());
}

inline Quat fromMrpt(const mrpt::math::CQuaternionDouble& q) {
  return canonical(Quat(q.r(), q.x(), q.y(), q.z()));
}

/// A pose with zero translation and rotation q_ib (the body in the inertial frame).
inline mrpt::poses::CPose3DQuat toPose3DQuat(const Quat& q_ib) {
  return mrpt::poses::CPose3DQuat(0, 0, 0, toMrpt(q_ib));
}

inline Quat fromPose3DQuat(const mrpt::poses::CPose3DQuat& p) { return fromMrpt(p.quat()); }

/// A mounting written as MRPT CPose3D yaw pitch roll [deg] (the ini keys *_ypr_deg): the
/// rotation-only pose, body from sensor.
inline mrpt::poses::CPose3D mountingPose(const Vec3& ypr_deg) {
  const Vec3 ypr = ypr_deg * kRadPerDeg;
  return mrpt::poses::CPose3D(0, 0, 0, ypr.x(), ypr.y(), ypr.z());
}

/// Julian year of an MRPT timestamp (for catalog epoch propagation).
inline double julianYear(const mrpt::Clock::time_point& t) {
  return julianYearFromUnixSeconds(mrpt::Clock::toDouble(t));
}

/// The timestamp `t` seconds after the Unix time `start_unix_s`, exact to the clock tick
/// (the whole seconds are converted apart from the fraction, which a double of ~1.7e9 s
/// would round to ~0.2 us). Every clock built from a start time and an offset (a scenario,
/// a camera folder of known frame rate) stamps through here, so equal times are equal ticks.
inline mrpt::Clock::time_point timestampAfter(double start_unix_s, double t) {
  const double whole = std::floor(start_unix_s);
  const auto t0 = mrpt::Clock::fromDouble(whole);
  const std::chrono::duration<double> offset(start_unix_s - whole + t);
  return t0 + std::chrono::duration_cast<mrpt::Clock::duration>(offset);
}

}  // namespace st

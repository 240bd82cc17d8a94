/// @file mrpt_convert.hpp
/// The only place where attitudes cross between Eigen and MRPT types (header-only; users
/// link mrpt::poses). MRPT CQuaternion stores (w, x, y, z) with [0] = w; Eigen's coeffs()
/// are (x, y, z, w): always go through these functions, never Map one onto the other.
#pragma once
#include <mrpt/core/Clock.h>
#include <mrpt/math/CQuaternion.h>
#include <mrpt/poses/CPose3DQuat.h>

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

/// Julian year of an MRPT timestamp (for catalog epoch propagation).
inline double julianYear(const mrpt::Clock::time_point& t) {
  return julianYearFromUnixSeconds(mrpt::Clock::toDouble(t));
}

}  // namespace st

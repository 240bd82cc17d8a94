#include "sensors/sim/motion.hpp"

#include <cmath>

#include "common/conventions.hpp"
#include "common/errors.hpp"

namespace st {

// ---------------------------------------------------------------- slew with acceleration

SlewAccelMotion::SlewAccelMotion(const Quat& q0_ib, const Vec3& axis_body, double max_rate,
                                 double accel, double coast_s, double start_s)
    : q0_(canonical(q0_ib)),
      axis_(axis_body.normalized()),
      max_rate_(max_rate),
      accel_(accel),
      coast_(coast_s),
      start_(start_s),
      ramp_(max_rate / accel) {}

double SlewAccelMotion::rateMagnitude(double t) const {
  const double u = t - start_;
  if (u <= 0) return 0;
  if (u < ramp_) return accel_ * u;
  if (u <= ramp_ + coast_) return max_rate_;
  const double d = u - ramp_ - coast_;  // time into the deceleration
  if (d < ramp_) return max_rate_ - accel_ * d;
  return 0;
}

double SlewAccelMotion::angle(double t) const {
  const double u = t - start_;
  if (u <= 0) return 0;
  const double ramp_angle = 0.5 * accel_ * ramp_ * ramp_;
  if (u < ramp_) return 0.5 * accel_ * u * u;
  if (u <= ramp_ + coast_) return ramp_angle + max_rate_ * (u - ramp_);
  const double d = std::min(u - ramp_ - coast_, ramp_);
  return ramp_angle + max_rate_ * coast_ + max_rate_ * d - 0.5 * accel_ * d * d;
}

Quat SlewAccelMotion::attitude(double t) const {
  return canonical(q0_ * quatExp(axis_ * angle(t)));
}

Vec3 SlewAccelMotion::rateBody(double t) const { return axis_ * rateMagnitude(t); }

// ---------------------------------------------------------------- integrated profiles

IntegratedMotion::IntegratedMotion(const Quat& q0_ib, const Vec3& w0_body, double step_s)
    : h_(step_s) {
  const Quat q = canonical(q0_ib);
  s0_ << q.w(), q.x(), q.y(), q.z(), w0_body;
  checkpoints_.push_back(s0_);
}

IntegratedMotion::State IntegratedMotion::derivative(double t, const State& s) const {
  // Seed 002 eq. 10 in Hamilton scalar-first form: q_dot = 1/2 q (x) (0, w), w in body.
  const Vec3 w = omega(t, s.tail<3>());
  const double qw = s[0], qx = s[1], qy = s[2], qz = s[3];
  State d;
  d[0] = 0.5 * (-qx * w.x() - qy * w.y() - qz * w.z());
  d[1] = 0.5 * (qw * w.x() + qy * w.z() - qz * w.y());
  d[2] = 0.5 * (qw * w.y() + qz * w.x() - qx * w.z());
  d[3] = 0.5 * (qw * w.z() + qx * w.y() - qy * w.x());
  d.tail<3>() = omegaDot(t, s.tail<3>());
  return d;
}

IntegratedMotion::State IntegratedMotion::rk4(double t, const State& s, double dt) const {
  const State k1 = derivative(t, s);
  const State k2 = derivative(t + 0.5 * dt, s + 0.5 * dt * k1);
  const State k3 = derivative(t + 0.5 * dt, s + 0.5 * dt * k2);
  const State k4 = derivative(t + dt, s + dt * k3);
  State out = s + (dt / 6.0) * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
  out.head<4>().normalize();  // keep |q| = 1 (RK4 drifts off the unit sphere at O(h^5))
  return out;
}

IntegratedMotion::State IntegratedMotion::stateAt(double t) const {
  if (t < 0) {  // backwards from t = 0, not cached (rare: only for samples before the start)
    State s = s0_;
    double tc = 0;
    while (tc - h_ > t) {
      s = rk4(tc, s, -h_);
      tc -= h_;
    }
    return rk4(tc, s, t - tc);
  }
  const double span = h_ * kCheckpointEvery;
  const std::size_t k = static_cast<std::size_t>(std::floor(t / span));
  State s;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    while (checkpoints_.size() <= k) {
      State c = checkpoints_.back();
      const std::size_t j = checkpoints_.size() - 1;
      for (int i = 0; i < kCheckpointEvery; ++i) c = rk4((j * kCheckpointEvery + i) * h_, c, h_);
      checkpoints_.push_back(c);
    }
    s = checkpoints_[k];
  }
  // Whole grid steps from the checkpoint, then one partial step: the same arithmetic as
  // the cache, so the result does not depend on which times were queried before.
  std::size_t n = k * kCheckpointEvery;
  while ((n + 1) * h_ <= t) {
    s = rk4(n * h_, s, h_);
    ++n;
  }
  const double rest = t - n * h_;
  return rest > 0 ? rk4(n * h_, s, rest) : s;
}

Quat IntegratedMotion::attitude(double t) const {
  const State s = stateAt(t);
  return canonical(Quat(s[0], s[1], s[2], s[3]));
}

Vec3 IntegratedMotion::rateBody(double t) const {
  const State s = stateAt(t);
  return omega(t, s.tail<3>());
}

JitterMotion::JitterMotion(const Quat& q0_ib, const Vec3& base, const Vec3& amplitude,
                           const Vec3& freq_hz, const Vec3& phase, double step_s)
    : IntegratedMotion(q0_ib, Vec3::Zero(), step_s),
      base_(base),
      amp_(amplitude),
      freq_(freq_hz),
      phase_(phase) {}

Vec3 JitterMotion::prescribed(double t) const {
  Vec3 w;
  for (int k = 0; k < 3; ++k)
    w[k] = base_[k] + amp_[k] * std::sin(kTwoPi * freq_[k] * t + phase_[k]);
  return w;
}

Vec3 JitterMotion::omegaDot(double t, const Vec3&) const {
  Vec3 d;
  for (int k = 0; k < 3; ++k) {
    const double wf = kTwoPi * freq_[k];
    d[k] = amp_[k] * wf * std::cos(wf * t + phase_[k]);
  }
  return d;
}

TumbleMotion::TumbleMotion(const Quat& q0_ib, const Vec3& rate0_body, const Vec3& inertia,
                           double step_s)
    : IntegratedMotion(q0_ib, rate0_body, step_s), inertia_(inertia) {}

Vec3 TumbleMotion::omegaDot(double, const Vec3& w) const {
  // Euler's equations without torque: I w_dot = -w x (I w).
  const Vec3 Iw = inertia_.cwiseProduct(w);
  return (-w.cross(Iw)).cwiseQuotient(inertia_);
}

}  // namespace st

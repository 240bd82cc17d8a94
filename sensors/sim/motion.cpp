#include "sensors/sim/motion.hpp"

#include <mrpt/config/CConfigFileBase.h>

#include <cmath>
#include <cstdlib>
#include <sstream>

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

// ---------------------------------------------------------------- configuration

namespace {

std::string where(const std::string& section, const std::string& key) {
  return "motion section [" + section + "] key '" + key + "'";
}

double parseNumber(const std::string& text, const std::string& section, const std::string& key) {
  const char* begin = text.c_str();
  char* end = nullptr;
  const double v = std::strtod(begin, &end);
  while (end && (*end == ' ' || *end == '\t')) ++end;
  if (end == begin || *end != '\0' || !std::isfinite(v))
    throw InputError(where(section, key) + " = '" + text + "': not a number");
  return v;
}

double readDouble(const mrpt::config::CConfigFileBase& cfg, const std::string& section,
                  const std::string& key, const double* fallback) {
  if (!cfg.keyExists(section, key)) {
    if (!fallback) throw InputError(where(section, key) + " is required");
    return *fallback;
  }
  return parseNumber(cfg.read_string(section, key, ""), section, key);
}

Vec3 readVec3(const mrpt::config::CConfigFileBase& cfg, const std::string& section,
              const std::string& key, const Vec3* fallback) {
  if (!cfg.keyExists(section, key)) {
    if (!fallback) throw InputError(where(section, key) + " is required (three numbers)");
    return *fallback;
  }
  std::string text = cfg.read_string(section, key, "");
  for (char& c : text)
    if (c == ',') c = ' ';
  std::istringstream in(text);
  std::vector<std::string> parts;
  for (std::string p; in >> p;) parts.push_back(p);
  if (parts.size() != 3)
    throw InputError(where(section, key) + " = '" + text + "': expected three numbers");
  return Vec3(parseNumber(parts[0], section, key), parseNumber(parts[1], section, key),
              parseNumber(parts[2], section, key));
}

double positive(double v, const std::string& section, const std::string& key) {
  if (!(v > 0)) throw InputError(where(section, key) + " must be > 0");
  return v;
}

double nonNegative(double v, const std::string& section, const std::string& key) {
  if (!(v >= 0)) throw InputError(where(section, key) + " must be >= 0");
  return v;
}

double readStep(const mrpt::config::CConfigFileBase& cfg, const std::string& s) {
  const double def = 1e-3;
  const double h = positive(readDouble(cfg, s, "step_s", &def), s, "step_s");
  if (h > 0.1) throw InputError(where(s, "step_s") + " must be <= 0.1 s");
  return h;
}

using Maker = std::unique_ptr<MotionProfile> (*)(const mrpt::config::CConfigFileBase&,
                                                 const std::string&, const Quat&);

std::unique_ptr<MotionProfile> makeHold(const mrpt::config::CConfigFileBase&, const std::string&,
                                        const Quat& q0) {
  return std::make_unique<HoldMotion>(q0);
}

std::unique_ptr<MotionProfile> makeSlew(const mrpt::config::CConfigFileBase& cfg,
                                        const std::string& s, const Quat& q0) {
  return std::make_unique<SlewMotion>(q0, readVec3(cfg, s, "rate_deg_s", nullptr) * kRadPerDeg);
}

std::unique_ptr<MotionProfile> makeSlewAccel(const mrpt::config::CConfigFileBase& cfg,
                                             const std::string& s, const Quat& q0) {
  const Vec3 def_axis(0, 1, 0);
  const Vec3 axis = readVec3(cfg, s, "axis", &def_axis);
  if (!(axis.norm() > 0)) throw InputError(where(s, "axis") + " must be a non-zero vector");
  const double max_rate =
      positive(readDouble(cfg, s, "max_rate_deg_s", nullptr), s, "max_rate_deg_s");
  const double accel = positive(readDouble(cfg, s, "accel_deg_s2", nullptr), s, "accel_deg_s2");
  const double def_coast = 10, def_start = 0;
  const double coast = nonNegative(readDouble(cfg, s, "coast_s", &def_coast), s, "coast_s");
  const double start = nonNegative(readDouble(cfg, s, "start_s", &def_start), s, "start_s");
  return std::make_unique<SlewAccelMotion>(q0, axis, max_rate * kRadPerDeg, accel * kRadPerDeg,
                                           coast, start);
}

std::unique_ptr<MotionProfile> makeJitter(const mrpt::config::CConfigFileBase& cfg,
                                          const std::string& s, const Quat& q0) {
  const Vec3 zero = Vec3::Zero();
  const Vec3 base = readVec3(cfg, s, "base_rate_deg_s", &zero) * kRadPerDeg;
  const Vec3 amp = readVec3(cfg, s, "amplitude_deg_s", nullptr) * kRadPerDeg;
  const Vec3 freq = readVec3(cfg, s, "frequency_hz", nullptr);
  if ((freq.array() < 0).any()) throw InputError(where(s, "frequency_hz") + " must be >= 0");
  const Vec3 phase = readVec3(cfg, s, "phase_deg", &zero) * kRadPerDeg;
  return std::make_unique<JitterMotion>(q0, base, amp, freq, phase, readStep(cfg, s));
}

std::unique_ptr<MotionProfile> makeTumble(const mrpt::config::CConfigFileBase& cfg,
                                          const std::string& s, const Quat& q0) {
  const Vec3 rate = readVec3(cfg, s, "rate_deg_s", nullptr) * kRadPerDeg;
  const Vec3 def_inertia(1, 2, 3);
  const Vec3 inertia = readVec3(cfg, s, "inertia", &def_inertia);
  if ((inertia.array() <= 0).any()) throw InputError(where(s, "inertia") + " must be > 0");
  return std::make_unique<TumbleMotion>(q0, rate, inertia, readStep(cfg, s));
}

struct Entry {
  const char* name;
  Maker make;
};
// The one registry table: type names (and the error message listing them) come from here.
const Entry kRegistry[] = {
    {"hold", &makeHold},     {"slew", &makeSlew},     {"slew_accel", &makeSlewAccel},
    {"jitter", &makeJitter}, {"tumble", &makeTumble},
};

}  // namespace

std::vector<std::string> MotionProfile::types() {
  std::vector<std::string> out;
  for (const Entry& e : kRegistry) out.push_back(e.name);
  return out;
}

std::unique_ptr<MotionProfile> MotionProfile::fromConfig(const mrpt::config::CConfigFileBase& cfg,
                                                         const std::string& section) {
  const std::string type = cfg.read_string(section, "type", "");
  const double zero = 0;
  RaDecRoll rdr;
  rdr.ra = readDouble(cfg, section, "ra_deg", &zero) * kRadPerDeg;
  rdr.dec = readDouble(cfg, section, "dec_deg", &zero) * kRadPerDeg;
  rdr.roll = readDouble(cfg, section, "roll_deg", &zero) * kRadPerDeg;
  if (std::abs(rdr.dec) > 0.5 * kPi + 1e-12)
    throw InputError(where(section, "dec_deg") + " must be in [-90, 90]");
  const Quat q0 = attitudeFromRaDecRoll(rdr);
  for (const Entry& e : kRegistry)
    if (type == e.name) return e.make(cfg, section, q0);
  std::string names;
  for (const Entry& e : kRegistry) names += std::string(names.empty() ? "" : ", ") + e.name;
  throw InputError(where(section, "type") + " = '" + type + "': expected one of " + names);
}

}  // namespace st

// The motion section of a scenario: one schema per profile type (motion.hpp lists the keys),
// and the profiles built from the keys read through it.
#include <mrpt/config/CConfigFileBase.h>

#include <cmath>
#include <map>

#include "common/conventions.hpp"
#include "common/errors.hpp"
#include "sensors/sim/motion.hpp"

namespace st {

namespace {

using K = MotionKeys;
using Schema = SectionSchema<K>;

void requirePositive(double v, const std::string& where, const char* key) {
  if (!(v > 0)) throw InputError(where + " key '" + key + "' must be > 0");
}
void requireNonNegative(double v, const std::string& where, const char* key) {
  if (!(v >= 0)) throw InputError(where + " key '" + key + "' must be >= 0");
}
double checkedStep(const K& k, const std::string& where) {
  requirePositive(k.step_s, where, "step_s");
  if (k.step_s > 0.1) throw InputError(where + " key 'step_s' must be <= 0.1 s");
  return k.step_s;
}

Schema common(const std::vector<std::string>& types) {
  return Schema()
      .choice("type", &K::type, types, "motion profile")
      .required()
      .add("ra_deg", &K::ra_deg, "[deg] initial boresight right ascension")
      .add("dec_deg", &K::dec_deg, "[deg] initial boresight declination, -90..90")
      .add("roll_deg", &K::roll_deg, "[deg] initial roll about the boresight");
}
void addStep(Schema& s) { s.add("step_s", &K::step_s, "[s] integration step, <= 0.1"); }

using Maker = std::unique_ptr<MotionProfile> (*)(const K&, const std::string&, const Quat&);
using Keys = void (*)(Schema&);

std::unique_ptr<MotionProfile> makeHold(const K&, const std::string&, const Quat& q0) {
  return std::make_unique<HoldMotion>(q0);
}
void holdKeys(Schema&) {}

std::unique_ptr<MotionProfile> makeSlew(const K& k, const std::string&, const Quat& q0) {
  return std::make_unique<SlewMotion>(q0, k.rate_deg_s * kRadPerDeg);
}
void slewKeys(Schema& s) {
  s.add("rate_deg_s", &K::rate_deg_s, "[deg/s] wx wy wz constant body rate").required();
}

std::unique_ptr<MotionProfile> makeSlewAccel(const K& k, const std::string& w, const Quat& q0) {
  if (!(k.axis.norm() > 0)) throw InputError(w + " key 'axis' must be a non-zero vector");
  requirePositive(k.max_rate_deg_s, w, "max_rate_deg_s");
  requirePositive(k.accel_deg_s2, w, "accel_deg_s2");
  requireNonNegative(k.coast_s, w, "coast_s");
  requireNonNegative(k.start_s, w, "start_s");
  return std::make_unique<SlewAccelMotion>(q0, k.axis, k.max_rate_deg_s * kRadPerDeg,
                                           k.accel_deg_s2 * kRadPerDeg, k.coast_s, k.start_s);
}
void slewAccelKeys(Schema& s) {
  s.add("axis", &K::axis, "x y z body rotation axis (normalised)")
      .add("max_rate_deg_s", &K::max_rate_deg_s, "[deg/s] peak rate, > 0")
      .required()
      .add("accel_deg_s2", &K::accel_deg_s2, "[deg/s^2] ramp acceleration, > 0")
      .required()
      .add("coast_s", &K::coast_s, "[s] time at the peak rate, >= 0")
      .add("start_s", &K::start_s, "[s] start of the ramp, >= 0");
}

std::unique_ptr<MotionProfile> makeJitter(const K& k, const std::string& w, const Quat& q0) {
  if ((k.frequency_hz.array() < 0).any()) throw InputError(w + " key 'frequency_hz' must be >= 0");
  return std::make_unique<JitterMotion>(q0, k.base_rate_deg_s * kRadPerDeg,
                                        k.amplitude_deg_s * kRadPerDeg, k.frequency_hz,
                                        k.phase_deg * kRadPerDeg, checkedStep(k, w));
}
void jitterKeys(Schema& s) {
  s.add("base_rate_deg_s", &K::base_rate_deg_s, "[deg/s] wx wy wz mean body rate")
      .add("amplitude_deg_s", &K::amplitude_deg_s, "[deg/s] ax ay az sine amplitude")
      .required()
      .add("frequency_hz", &K::frequency_hz, "[Hz] fx fy fz sine frequency, >= 0")
      .required()
      .add("phase_deg", &K::phase_deg, "[deg] px py pz sine phase");
  addStep(s);
}

std::unique_ptr<MotionProfile> makeTumble(const K& k, const std::string& w, const Quat& q0) {
  if ((k.inertia.array() <= 0).any()) throw InputError(w + " key 'inertia' must be > 0");
  return std::make_unique<TumbleMotion>(q0, k.rate_deg_s * kRadPerDeg, k.inertia,
                                        checkedStep(k, w));
}
void tumbleKeys(Schema& s) {
  s.add("rate_deg_s", &K::rate_deg_s, "[deg/s] wx wy wz initial body rate").required()
      .add("inertia", &K::inertia, "Ixx Iyy Izz principal moments of inertia, > 0");
  addStep(s);
}

struct Entry {
  const char* name;
  Maker make;
  Keys keys;
};
// The one registry table: type names, their keys and their makers come from here.
const Entry kRegistry[] = {
    {"hold", &makeHold, &holdKeys},
    {"slew", &makeSlew, &slewKeys},
    {"slew_accel", &makeSlewAccel, &slewAccelKeys},
    {"jitter", &makeJitter, &jitterKeys},
    {"tumble", &makeTumble, &tumbleKeys},
};

const Entry* findType(const std::string& type) {
  for (const Entry& e : kRegistry)
    if (type == e.name) return &e;
  return nullptr;
}

}  // namespace

std::vector<std::string> MotionProfile::types() {
  std::vector<std::string> out;
  for (const Entry& e : kRegistry) out.push_back(e.name);
  return out;
}

const SectionSchema<MotionKeys>& motionSchema(const std::string& type) {
  static const std::map<std::string, Schema> schemas = [] {
    std::map<std::string, Schema> m;
    for (const Entry& e : kRegistry) {
      Schema s = common(MotionProfile::types());
      e.keys(s);
      m.emplace(e.name, std::move(s));
    }
    return m;
  }();
  const auto it = schemas.find(type);
  if (it == schemas.end()) throw InputError("motion type '" + type + "': unknown");
  return it->second;
}

MotionKeys readMotionKeys(const IniReader& r, const std::string& section) {
  MotionKeys k;
  // The type decides which keys are valid: read and check it first.
  k.type = r.str(section, "type", "");
  if (k.type.empty()) throw InputError(r.whereKey(section, "type") + ": missing key (motion profile)");
  if (!findType(k.type)) throwBadChoice(r, section, "type", k.type, MotionProfile::types());
  motionSchema(k.type).read(r, section, k);
  return k;
}

std::unique_ptr<MotionProfile> MotionProfile::fromKeys(const MotionKeys& k, const std::string& where) {
  if (std::abs(k.dec_deg) > 90 + 1e-10) throw InputError(where + " key 'dec_deg' must be in [-90, 90]");
  const Quat q0 = attitudeFromRaDecRoll(RaDecRoll{k.ra_deg * kRadPerDeg, k.dec_deg * kRadPerDeg,
                                                  k.roll_deg * kRadPerDeg});
  const Entry* e = findType(k.type);
  if (!e) throw InputError(where + " key 'type' = '" + k.type + "': unknown motion type");
  return e->make(k, where, q0);
}

std::unique_ptr<MotionProfile> MotionProfile::fromConfig(const mrpt::config::CConfigFileBase& cfg,
                                                         const std::string& section) {
  const IniReader r{cfg, ""};
  return fromKeys(readMotionKeys(r, section), r.where(section));
}

}  // namespace st

#include "sensors/sim/gyro_model.hpp"

#include <cmath>
#include <cstdlib>

#include "common/conventions.hpp"
#include "common/errors.hpp"
#include "sensors/sim/motion.hpp"

namespace st {

namespace {
constexpr double kSecondsPerHour = 3600.0;
constexpr double kRootSecondsPerHour = 60.0;  // sqrt(3600 s)

}  // namespace

double GyroParams::sigmaV() const { return arw_deg_rt_h * kRadPerDeg / kRootSecondsPerHour; }
double GyroParams::sigmaU() const {
  return rrw_deg_h_rt_h * kRadPerDeg / kSecondsPerHour / kRootSecondsPerHour;
}
double GyroParams::constantBias() const { return bias_deg_h * kRadPerDeg / kSecondsPerHour; }

std::string GyroParams::validate() const {
  if (!(rate_hz > 0) || !std::isfinite(rate_hz)) return "rate_hz must be > 0";
  if (!(arw_deg_rt_h >= 0)) return "arw_deg_rt_h must be >= 0";
  if (!(rrw_deg_h_rt_h >= 0)) return "rrw_deg_h_rt_h must be >= 0";
  if (!std::isfinite(bias_deg_h)) return "bias_deg_h must be finite";
  if (!std::isfinite(scale_factor_ppm)) return "scale_factor_ppm must be finite";
  if (!(quantum_rad_s >= 0)) return "quantum_rad_s must be >= 0";
  return {};
}

const SectionSchema<GyroParams>& gyroParamsSchema() {
  using G = GyroParams;
  static const auto schema =
      SectionSchema<G>()
          .add("rate_hz", &G::rate_hz, "[Hz] sample rate, > 0")
          .required()
          .range(0.01, 10000)
          .add("arw_deg_rt_h", &G::arw_deg_rt_h, "[deg/sqrt(h)] angle random walk, >= 0")
          .range(0, 100)
          .add("rrw_deg_h_rt_h", &G::rrw_deg_h_rt_h, "[deg/h/sqrt(h)] rate random walk, >= 0")
          .range(0, 1000)
          .add("bias_deg_h", &G::bias_deg_h, "[deg/h] constant bias on every axis")
          .range(-1e5, 1e5)
          .add("scale_factor_ppm", &G::scale_factor_ppm, "[ppm] scale factor error")
          .range(-1e6, 1e6)
          .add("quantum_rad_s", &G::quantum_rad_s, "[rad/s] output quantum; 0 = none")
          .range(0, 1);
  return schema;
}

GyroParams GyroParams::fromConfig(const mrpt::config::CConfigFileBase& cfg,
                                  const std::string& section) {
  return fromConfig(IniReader{cfg, "gyro"}, section);
}

GyroParams GyroParams::fromConfig(const IniReader& r, const std::string& section) {
  GyroParams p;
  gyroParamsSchema().read(r, section, p);
  const std::string err = p.validate();
  if (!err.empty()) throw InputError(r.where(section) + ": " + err);
  return p;
}

GyroSimulator::GyroSimulator(const GyroParams& params, uint64_t seed, Vec3 initial_bias_rad_s)
    : params_(params),
      rng_(seed),
      bias_(initial_bias_rad_s + Vec3::Constant(params.constantBias())) {}

double GyroSimulator::normal() {
  // Box-Muller (polar-free form), both values used: portable across standard libraries.
  if (have_spare_) {
    have_spare_ = false;
    return spare_;
  }
  constexpr double kScale = 1.0 / 9007199254740992.0;  // 2^-53
  double u1;
  do {
    u1 = static_cast<double>(rng_() >> 11) * kScale;
  } while (u1 <= 0.0);
  const double u2 = static_cast<double>(rng_() >> 11) * kScale;
  const double r = std::sqrt(-2.0 * std::log(u1));
  spare_ = r * std::sin(kTwoPi * u2);
  have_spare_ = true;
  return r * std::cos(kTwoPi * u2);
}

Vec3 GyroSimulator::sample(const MotionProfile& truth, double t0, double t1) {
  const double dt = t1 - t0;
  if (!(dt > 0)) return truth.rateBody(t1) + bias_;  // precondition broken: no noise, no step
  // Mean true rate: the constant rate that carries q(t0) to q(t1) exactly.
  const Vec3 mean_rate = quatLog(truth.attitude(t0).conjugate() * truth.attitude(t1)) / dt;
  const double sv = params_.sigmaV(), su = params_.sigmaU();
  // M&C eq. 6.88 discretisation: white part sigma_v^2/dt plus the within-step RRW part.
  const double sigma_meas = std::sqrt(sv * sv / dt + su * su * dt / 12.0);
  const double sigma_walk = su * std::sqrt(dt);
  Vec3 noise, walk;
  for (int k = 0; k < 3; ++k) noise[k] = sigma_meas * normal();
  for (int k = 0; k < 3; ++k) walk[k] = sigma_walk * normal();
  const Vec3 b_next = bias_ + walk;
  Vec3 out = (1.0 + 1e-6 * params_.scale_factor_ppm) * mean_rate + 0.5 * (bias_ + b_next) + noise;
  bias_ = b_next;
  if (params_.quantum_rad_s > 0) {
    const double qn = params_.quantum_rad_s;
    const Vec3 v = out + quant_residual_;
    for (int k = 0; k < 3; ++k) out[k] = qn * std::round(v[k] / qn);
    quant_residual_ = v - out;
  }
  return out;
}

}  // namespace st

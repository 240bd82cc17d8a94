/// @file gyro_model.hpp
/// Simulated rate gyro (three orthogonal axes aligned with the body frame).
///
/// Continuous model (Farrenkopf; Markley & Crassidis, Fundamentals of Spacecraft Attitude
/// Determination and Control, sec. 4.7.1):
///     w_meas = (1 + s) w_true + b + eta_v,     b_dot = eta_u,
///     E[eta_v eta_v^T] = sigma_v^2 I delta(t),  E[eta_u eta_u^T] = sigma_u^2 I delta(t)
/// with sigma_v = angle random walk (ARW) and sigma_u = rate random walk (RRW).
///
/// Discrete output over [t0, t1], dt = t1 - t0 (the form the MEKF's Q assumes, M&C eq. 6.88):
///     w_k   = (1 + s) * mean_true_rate + (b_k + b_k+1)/2 + sqrt(sigma_v^2/dt + sigma_u^2 dt/12)
///     N_v b_k+1 = b_k + sigma_u sqrt(dt) N_u
/// where mean_true_rate = Log(q(t0)^-1 q(t1)) / dt, the constant body rate that carries
/// q(t0) exactly to q(t1), so integrating noiseless measurements reproduces the truth.
/// Quantisation rounds to multiples of quantum_rad_s and carries the remainder to the next
/// sample (as an integrating gyro does), so the integrated angle error stays below one quantum.
///
/// Units at the edge (standard datasheet units):
///   arw_deg_rt_h   [deg/sqrt(h)]    -> sigma_v [rad/sqrt(s)] = arw * (pi/180) / 60
///   rrw_deg_h_rt_h [deg/h/sqrt(h)]  -> sigma_u [rad/s^1.5]   = rrw * (pi/180) / 3600 / 60
///   bias_deg_h     [deg/h]          -> constant bias added on every axis, [rad/s]
///
/// .ini keys (section given by the caller): rate_hz (required, > 0), arw_deg_rt_h,
/// rrw_deg_h_rt_h, bias_deg_h, scale_factor_ppm, quantum_rad_s (all default 0, >= 0 except
/// bias and scale factor, which may be negative).
///
/// Randomness: std::mt19937_64 with a Box-Muller normal draw written here, so a seed gives
/// the same samples with any standard library.
#pragma once
#include <cstdint>
#include <random>
#include <string>

#include "common/attitude.hpp"
#include "config/schema.hpp"

namespace mrpt::config {
class CConfigFileBase;
}

namespace st {

class MotionProfile;

struct GyroParams {
  double rate_hz = 0;  ///< required in .ini files (0 is invalid)
  double arw_deg_rt_h = 0;
  double rrw_deg_h_rt_h = 0;
  double bias_deg_h = 0;
  double scale_factor_ppm = 0;
  double quantum_rad_s = 0;
  static GyroParams fromConfig(const mrpt::config::CConfigFileBase&, const std::string& section);
  /// Strict read through gyroParamsSchema() (InputError names file, section and key).
  static GyroParams fromConfig(const IniReader& r, const std::string& section);

  double sigmaV() const;        ///< ARW [rad/sqrt(s)]
  double sigmaU() const;        ///< RRW [rad/s^1.5]
  double constantBias() const;  ///< [rad/s]
  /// Empty when valid, otherwise the reason (names the field).
  std::string validate() const;
};

/// The gyro keys above, bound to GyroParams.
const SectionSchema<GyroParams>& gyroParamsSchema();

class GyroSimulator {
 public:
  /// initial_bias_rad_s: the run's turn-on bias (e.g. drawn by the scenario), added to the
  /// constant bias of the params; the random walk starts from their sum.
  GyroSimulator(const GyroParams&, uint64_t seed, Vec3 initial_bias_rad_s);
  /// Measured mean rate over [t0, t1] given the exact motion; advances the bias random walk.
  /// Precondition: t1 > t0.
  Vec3 sample(const MotionProfile& truth, double t0, double t1);
  Vec3 bias() const { return bias_; }  ///< current true bias [rad/s]
  const GyroParams& params() const { return params_; }

 private:
  double normal();

  GyroParams params_;
  std::mt19937_64 rng_;
  Vec3 bias_;
  Vec3 quant_residual_ = Vec3::Zero();
  bool have_spare_ = false;
  double spare_ = 0;
};

}  // namespace st

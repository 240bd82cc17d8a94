/// @file gyro_health.hpp
/// Sample-level health checks of a rate gyro, per axis of the gyro's own frame, run by the
/// fusion loop on every sample before the filter sees it (issue 18 item 6). Each check
/// compares the samples with what the gyro's datasheet white noise allows: per-sample
/// sigma_s = sigma_v / sqrt(dt) (ARW spectral density over one sample interval), plus the
/// body's dynamics, bounded by max_angular_accel.
///
///  - spike: a sample further than
///      spike_sigmas * sigma_s * sqrt(1 + pi / (2 m)) + max_accel * dt * (m + 1) / 2
///    from the median of the last m accepted samples (the median of m normal samples has a
///    variance of about pi / (2 m) sigma^2; it lags a ramp by (m + 1) / 2 samples) is replaced
///    by that median. At spike_sigmas = 10 a healthy sample is flagged with p ~ 1e-23.
///    `step_after` flagged samples in a row that agree with each other within the same bound
///    are a real rate step (e.g. a thruster), not spikes: they are accepted, and the error of
///    the samples replaced before (sum of (raw - median) dt) is handed to the loop, which adds
///    it to the filter's attitude covariance;
///  - stuck: an axis whose reading repeats bit for bit in at least half of the last `window`
///    samples while another axis does not (white noise of sigma_s makes exact repeats
///    impossible for a float reading and rare, p ~ lsb / (2 sqrt(pi) sigma_s), for a reading
///    quantised at lsb << sigma_s: at lsb = sigma_s / 4, 10 of 20 repeats has p ~ 1e-7). All
///    three axes repeating is a still, noise-free (simulated) gyro, not a fault;
///  - noisy: the median |second difference| of the last `window` samples above noise_factor
///    times its healthy value 0.674 sqrt(6) sigma_s (the second difference cancels a
///    constant angular acceleration; a median ignores isolated spikes); for 20 samples,
///    10 of them above 4x that has p ~ 1e-15. Also noisy, and found sooner: `noisy_flags`
///    spikes flagged on one axis within the window (noise far above the datasheet's makes
///    most samples spikes).
/// An axis found stuck or noisy makes the gyro unhealthy until `window` samples in a row pass
/// every check on every axis.
#pragma once
#include <array>
#include <deque>
#include <string>

#include "common/attitude.hpp"
#include "common/conventions.hpp"

namespace st {

struct GyroHealthOptions {
  bool enabled = true;
  /// [rad/s^2] the body's largest angular acceleration (10 deg/s^2: far above a star
  /// tracker's slews and jitter; 0.7 deg/s^2 in the fault scenarios' jitter).
  double max_angular_accel_rad_s2 = deg2rad(10.0);
  double spike_sigmas = 10.0;
  int median_of = 5;    ///< accepted samples whose median a sample is compared with
  int step_after = 3;   ///< flagged samples in a row that agree: a real rate step
  int window = 20;      ///< samples of the stuck / noisy statistics and of the recovery
  double noise_factor = 4.0;
  /// Spikes flagged on one axis within the window that make it noisy. Independent spikes
  /// (Poisson, mean r = 0.13 per axis per 20 samples at 2 spikes/s on 100 Hz) reach 4 with
  /// p ~ r^4 / 24 ~ 1e-5 per window.
  int noisy_flags = 4;

  bool isValid(std::string* why = nullptr) const;
};

/// The verdict on one sample.
struct GyroSampleCheck {
  Vec3 rate;               ///< the rate to use (spikes replaced), gyro frame [rad/s]
  bool spike = false;      ///< some axis was replaced
  bool healthy = true;     ///< the gyro can be trusted after this sample
  bool changed = false;    ///< healthy differs from the previous sample's verdict
  Vec3 step_error = Vec3::Zero();  ///< [rad] a step accepted: the angle error of the
                                   ///< samples replaced before it (gyro frame)
  std::string why;         ///< changed: what was found ("axis y stuck ...") or the recovery
};

class GyroHealth {
 public:
  explicit GyroHealth(GyroHealthOptions o = {}) : o_(o) {}
  /// One sample (gyro frame, the mean rate over dt seconds), sigma_s the per-sample 1-sigma
  /// of the white rate noise [rad/s]. sigma_s <= 0 (a filter told of no noise) turns the
  /// stuck and noisy checks off (they need a noise to compare with).
  GyroSampleCheck check(const Vec3& rate, double dt, double sigma_s);
  bool healthy() const { return healthy_; }
  int spikes() const { return spikes_; }
  void reset();

 private:
  struct Axis {
    std::deque<double> accepted;  // last median_of accepted values
    std::deque<double> raw;       // last window + 2 raw values
    std::deque<bool> repeat, flag;  // per raw sample, last window
    std::deque<double> pending;     // flagged in a row: raw values
    double pending_error = 0;       // [rad] sum (raw - used) dt of those
  };
  GyroHealthOptions o_;
  std::array<Axis, 3> ax_;
  bool healthy_ = true;
  int clean_run_ = 0;
  int spikes_ = 0;
};

}  // namespace st

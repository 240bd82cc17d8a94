/// @file motion.hpp
/// Exact attitude truth for simulations: q_ib(t) and the body rate at any time t [s] from
/// the start of the run. The profiles of issue 4: inertial hold, constant-rate slew, slew
/// with a trapezoidal rate (accelerate, coast, decelerate), sinusoidal jitter and torque-free
/// tumbling. Hold, slew and slew_accel have closed forms; jitter and tumble are integrated
/// (RK4 on the quaternion kinematics q_dot = 1/2 q (x) (0, w), seed 002 eq. 10, on a fixed
/// fine grid with cached checkpoints), so attitude(t) and rateBody(t) agree to ~1e-12 rad.
///
/// Scenario .ini keys (section given by the caller; rates in deg/s, angles in degrees;
/// vectors are three numbers separated by spaces or commas):
///   type      = hold | slew | slew_accel | jitter | tumble             (required)
///   ra_deg, dec_deg, roll_deg = initial boresight and roll            (default 0 0 0)
///   slew:       rate_deg_s = wx wy wz                 body rate       (required)
///   slew_accel: axis = x y z (body, normalised)                       (default 0 1 0)
///               max_rate_deg_s, accel_deg_s2 (> 0)                    (required)
///               coast_s (>= 0, default 10), start_s (>= 0, default 0)
///               rate(t) = axis * trapezoid(t): 0 before start_s, ramp at accel_deg_s2 to
///               max_rate_deg_s, coast_s at the peak, ramp down to 0, then hold.
///   jitter:     base_rate_deg_s = wx wy wz                            (default 0 0 0)
///               amplitude_deg_s = ax ay az, frequency_hz = fx fy fz   (required)
///               phase_deg = px py pz                                  (default 0 0 0)
///               w_k(t) = base_k + amplitude_k * sin(2 pi f_k t + phase_k)
///               step_s = integration step (default 1e-3)
///   tumble:     rate_deg_s = initial body rate                        (required)
///               inertia = Ixx Iyy Izz principal moments, body axes    (default 1 2 3)
///               Torque-free Euler equations I w_dot = -w x (I w): a rate off the principal
///               axes nutates, and about the intermediate axis it flips (Dzhanibekov).
///               step_s = integration step (default 1e-3)
///
/// Thread safety: the integrated profiles fill a checkpoint cache lazily under a mutex, so
/// concurrent queries are safe; results do not depend on the order of queries.
#pragma once
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "common/attitude.hpp"
#include "config/schema.hpp"

namespace mrpt::config {
class CConfigFileBase;
}

namespace st {

/// The keys of a motion section (file comment), in .ini units; the keys a `type` accepts
/// are those of motionSchema(type).
struct MotionKeys {
  std::string type;
  double ra_deg = 0, dec_deg = 0, roll_deg = 0;
  Vec3 rate_deg_s = Vec3::Zero();       ///< slew, tumble
  Vec3 axis = Vec3(0, 1, 0);            ///< slew_accel
  double max_rate_deg_s = 0, accel_deg_s2 = 0, coast_s = 10, start_s = 0;
  Vec3 base_rate_deg_s = Vec3::Zero();  ///< jitter
  Vec3 amplitude_deg_s = Vec3::Zero(), frequency_hz = Vec3::Zero(), phase_deg = Vec3::Zero();
  double step_s = 1e-3;                 ///< jitter, tumble
  Vec3 inertia = Vec3(1, 2, 3);         ///< tumble
};
/// The schema of a motion section of type `type` (InputError for an unknown type).
const SectionSchema<MotionKeys>& motionSchema(const std::string& type);
/// Strict read of a motion section (its `type` first, then that type's keys).
MotionKeys readMotionKeys(const IniReader& r, const std::string& section);

class MotionProfile {  // exact truth: attitude and body rate at any time t [s] from the start
 public:
  virtual ~MotionProfile() = default;
  virtual Quat attitude(double t) const = 0;  ///< q_ib(t)
  virtual Vec3 rateBody(double t) const = 0;  ///< omega of body wrt inertial, body frame [rad/s]
  virtual std::string type() const = 0;       ///< the .ini `type` name

  /// Builds the profile of `section` (keys above). Throws InputError naming section/key/value.
  static std::unique_ptr<MotionProfile> fromConfig(const mrpt::config::CConfigFileBase& cfg,
                                                   const std::string& section);
  /// Builds the profile from keys read by readMotionKeys; `where` names the section.
  static std::unique_ptr<MotionProfile> fromKeys(const MotionKeys& k, const std::string& where);
  /// The accepted `type` names, from the one registry table.
  static std::vector<std::string> types();
};

/// Constant attitude.
class HoldMotion : public MotionProfile {
 public:
  explicit HoldMotion(const Quat& q0_ib) : q0_(canonical(q0_ib)) {}
  Quat attitude(double) const override { return q0_; }
  Vec3 rateBody(double) const override { return Vec3::Zero(); }
  std::string type() const override { return "hold"; }

 private:
  Quat q0_;
};

/// Constant body rate: q(t) = q0 (x) Exp(w t).
class SlewMotion : public MotionProfile {
 public:
  SlewMotion(const Quat& q0_ib, const Vec3& rate_body) : q0_(canonical(q0_ib)), w_(rate_body) {}
  Quat attitude(double t) const override { return canonical(q0_ * quatExp(w_ * t)); }
  Vec3 rateBody(double) const override { return w_; }
  std::string type() const override { return "slew"; }

 private:
  Quat q0_;
  Vec3 w_;
};

/// Rotation about a fixed body axis with a trapezoidal rate; the axis being fixed, the
/// attitude is exact: q(t) = q0 (x) Exp(axis * angle(t)), angle = integral of the rate.
class SlewAccelMotion : public MotionProfile {
 public:
  /// axis_body is normalised; max_rate [rad/s] > 0, accel [rad/s^2] > 0, coast, start [s] >= 0.
  SlewAccelMotion(const Quat& q0_ib, const Vec3& axis_body, double max_rate, double accel,
                  double coast_s, double start_s);
  Quat attitude(double t) const override;
  Vec3 rateBody(double t) const override;
  std::string type() const override { return "slew_accel"; }
  /// Rotation angle [rad] about the axis at time t (integral of the trapezoid).
  double angle(double t) const;
  /// Rate magnitude [rad/s] along the axis at time t.
  double rateMagnitude(double t) const;
  double endTime() const { return start_ + 2.0 * ramp_ + coast_; }

 private:
  Quat q0_;
  Vec3 axis_;
  double max_rate_, accel_, coast_, start_, ramp_;
};

/// Profiles without a closed-form attitude: the state (q, w) is integrated with RK4 on a
/// fixed grid of step h from t = 0; every kCheckpointEvery steps the state is cached, and a
/// query integrates from the nearest earlier checkpoint (grid steps, then one partial step).
/// Negative times integrate backwards from t = 0 without caching.
class IntegratedMotion : public MotionProfile {
 public:
  using State = Eigen::Matrix<double, 7, 1>;  ///< (qw, qx, qy, qz, wx, wy, wz)
  Quat attitude(double t) const override;
  Vec3 rateBody(double t) const override;
  double step() const { return h_; }
  static constexpr int kCheckpointEvery = 16;

 protected:
  IntegratedMotion(const Quat& q0_ib, const Vec3& w0_body, double step_s);
  /// Rate used by the kinematics at time t with state rate w (prescribed or integrated).
  virtual Vec3 omega(double t, const Vec3& w_state) const = 0;
  /// d w / dt at time t.
  virtual Vec3 omegaDot(double t, const Vec3& w_state) const = 0;

 private:
  State derivative(double t, const State& s) const;
  State rk4(double t, const State& s, double dt) const;
  State stateAt(double t) const;

  double h_;
  State s0_;
  mutable std::mutex mutex_;
  mutable std::vector<State> checkpoints_;  ///< state at k * kCheckpointEvery * h_
};

/// Body rate w_k(t) = base_k + amplitude_k sin(2 pi f_k t + phase_k) per axis.
class JitterMotion : public IntegratedMotion {
 public:
  /// Rates [rad/s], frequencies [Hz], phases [rad].
  JitterMotion(const Quat& q0_ib, const Vec3& base, const Vec3& amplitude, const Vec3& freq_hz,
               const Vec3& phase, double step_s = 1e-3);
  Vec3 rateBody(double t) const override { return prescribed(t); }
  std::string type() const override { return "jitter"; }

 private:
  Vec3 prescribed(double t) const;
  Vec3 omega(double t, const Vec3&) const override { return prescribed(t); }
  Vec3 omegaDot(double t, const Vec3&) const override;
  Vec3 base_, amp_, freq_, phase_;
};

/// Torque-free rigid body: I w_dot = -w x (I w), I = diag(inertia) in the body axes.
class TumbleMotion : public IntegratedMotion {
 public:
  TumbleMotion(const Quat& q0_ib, const Vec3& rate0_body, const Vec3& inertia,
               double step_s = 1e-3);
  std::string type() const override { return "tumble"; }
  const Vec3& inertia() const { return inertia_; }

 private:
  Vec3 omega(double, const Vec3& w) const override { return w; }
  Vec3 omegaDot(double, const Vec3& w) const override;
  Vec3 inertia_;
};

}  // namespace st

/// @file mekf.hpp
/// Multiplicative extended Kalman filter for attitude with gyro bias (Lefferts, Markley &
/// Shuster 1982; Markley & Crassidis, Fundamentals of Spacecraft Attitude Determination and
/// Control, ch. 6), in plain fixed-size Eigen (see MRPT-NOTES: not CKalmanFilterCapable).
///
/// State: global q_ib and gyro bias b [rad/s]. Error state x = [dtheta; db] (6), with the
/// attitude error in the BODY frame as in conventions.hpp: q_true = q_est (x) Exp(dtheta),
/// db = b_true - b_est. Gyro model of sensors/sim/gyro_model.hpp: w_meas = w + b + eta_v,
/// b_dot = eta_u, spectral densities sigma_v^2 (ARW) and sigma_u^2 (RRW).
///
/// Propagation over dt with a gyro sample w_meas (mean rate over the step):
///   w = w_meas - b;  q <- q (x) Exp(w dt)      (exact for a constant rate over the step;
///                                               seed 002 eq. 10 integrated in closed form)
///   P <- Phi P Phi^T + Q,  Phi = [Theta Psi; 0 I]   (M&C eq. 6.83, error dynamics
///        dtheta_dot = -[w x] dtheta - db - eta_v)
///   Q = [(sv^2 dt + su^2 dt^3/3) I, -(su^2 dt^2/2) I; -(su^2 dt^2/2) I, su^2 dt I] (M&C 6.93)
///
/// Updates (Joseph form, P symmetrised after each step, chi-square gated on the NIS):
///   attitude fix q_meas, 3x3 body covariance R: y = Log(q_est^-1 q_meas), H = [I 0].
///   star vectors (b body, r inertial): b_pred = R(q)^T r; the residual is taken in the
///     plane tangent to b_pred (basis E, 2 rows per star) so that the rank-2 QUEST
///     covariance sigma^2 (I - b b^T) is usable: y = E^T b_meas, H = E^T [b_pred x] [I 0]
///     (since R(q Exp(dtheta))^T r = b_pred + [b_pred x] dtheta to first order).
/// Reset after an update: q <- q (x) Exp(dtheta_hat), b <- b + db_hat; the second-order
/// covariance reset term is neglected (M&C sec. 6.2.2).
///
/// The API is built for a navigator: propagate with each gyro sample, predictAt() any
/// timestamp without changing the filter, then update.
///
/// Gyroless mode (MekfOptions::model = kGyroless, fusion/gyroless_model.hpp has Phi and Q):
/// the second 3-vector of the state is the body RATE w instead of the gyro bias (bias()
/// returns it, rate() names it), propagation needs no gyro sample (predictTo), and
/// updateRate() takes a measured rate. The updates and the reset are the same code.
#pragma once
#include <Eigen/Core>
#include <string>
#include <vector>

#include "common/attitude.hpp"
#include "common/conventions.hpp"

namespace st {

using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat6 = Eigen::Matrix<double, 6, 6>;

/// A gyro's datasheet units and the filter's, one place for both directions (fromDatasheet,
/// the [filter] keys of tracker.ini and the live .ini).
namespace gyro_units {
/// Angle random walk: [deg/sqrt(h)] <-> [rad/sqrt(s)] (sqrt(h) = 60 sqrt(s)).
inline double arwToFilter(double deg_rt_h) { return deg_rt_h * kRadPerDeg / 60.0; }
inline double arwToDatasheet(double rad_rt_s) { return rad_rt_s * 60.0 / kRadPerDeg; }
/// Rate random walk: [deg/h/sqrt(h)] <-> [rad/s/sqrt(s)].
inline double rrwToFilter(double deg_h_rt_h) { return deg_h_rt_h * kRadPerDeg / 3600.0 / 60.0; }
inline double rrwToDatasheet(double rad_s_rt_s) { return rad_s_rt_s * 60.0 * 3600.0 / kRadPerDeg; }
/// Bias: [deg/h] <-> [rad/s].
inline double biasToFilter(double deg_h) { return deg_h * kRadPerDeg / 3600.0; }
inline double biasToDatasheet(double rad_s) { return rad_s * 3600.0 / kRadPerDeg; }
}  // namespace gyro_units

struct MekfOptions {
  /// kGyro: state (q, gyro bias), propagated with gyro samples. kGyroless: state (q, body
  /// rate), constant-rate dynamics with a rate random walk (fusion/gyroless_model.hpp).
  enum class Model : uint8_t { kGyro, kGyroless };
  Model model = Model::kGyro;
  /// kGyroless: spectral density sw of the rate random walk [rad/s^2/sqrt(Hz)]: over T
  /// seconds the body rate wanders by sw sqrt(T) (1-sigma per axis).
  double rate_walk_rad_s2_rt_hz = 1e-3;
  double initial_rate_sigma_rad_s = 2.0 * kRadPerDeg;  ///< kGyroless: prior 1-sigma of the rate [rad/s] (2 deg/s)
  double arw_rad_rt_s = 0;                 ///< sigma_v: angle random walk [rad/sqrt(s)]
  double rrw_rad_s_rt_s = 0;               ///< sigma_u: rate random walk [rad/s^1.5]
  double initial_bias_sigma_rad_s = 1e-5;  ///< per-axis prior 1-sigma of the bias [rad/s]
  bool gate_enabled = true;
  double gate_probability = 0.999;  ///< chi-square gate: reject when NIS > quantile(p, dof)
  int max_star_vectors = 32;        ///< star-vector updates use at most this many stars

  /// From datasheet units: ARW [deg/sqrt(h)], RRW [deg/h/sqrt(h)], bias prior [deg/h].
  static MekfOptions fromDatasheet(double arw_deg_rt_h, double rrw_deg_h_rt_h,
                                   double initial_bias_sigma_deg_h);
  /// False (and the reason in *error) when a field is out of range.
  bool isValid(std::string* error = nullptr) const;
};

/// A star seen by the sensor and its catalog direction (tight coupling).
struct StarVectorMeasurement {
  Vec3 b;      ///< measured unit vector, body frame
  Vec3 r;      ///< catalog unit vector, inertial frame
  Mat3 cov_b;  ///< covariance of b [rad^2]; only the part across b is used
  /// Isotropic 1-sigma [rad] across the line of sight (QUEST model sigma^2 (I - b b^T)).
  static StarVectorMeasurement fromSigma(const Vec3& b, const Vec3& r, double sigma);
};

/// Outcome of one measurement update (also the innovation record of the per-step output).
struct MekfUpdateResult {
  bool accepted = false;
  std::string reason;              ///< empty when accepted; why otherwise
  Eigen::VectorXd innovation;      ///< y (3 for a fix, 2 per star)
  Eigen::MatrixXd innovation_cov;  ///< S = H P H^T + R
  double nis = 0;                  ///< y^T S^-1 y
  int dof = 0;
  double gate = 0;  ///< the threshold applied (infinity when the gate is off)
};

/// Prediction of the filter at a timestamp (the filter itself is not changed).
struct MekfPrediction {
  double t = 0;
  Quat q_ib = Quat::Identity();
  Vec3 bias = Vec3::Zero();  ///< kGyroless: the body rate
  Mat6 P = Mat6::Zero();
  Vec3 rate = Vec3::Zero();  ///< body rate [rad/s]: the state's (gyroless), else the last gyro's
  Mat3 attitudeCov() const { return P.topLeftCorner<3, 3>(); }
};

/// Per-step output of the filter.
struct MekfStep {
  enum class Event { kInit, kPropagate, kAttitudeFix, kStarVectors, kRate };
  Event event = Event::kInit;
  double t = 0;
  Quat q_ib = Quat::Identity();
  Vec3 bias = Vec3::Zero();
  Vec3 sigma_attitude = Vec3::Zero();  ///< 1-sigma per body axis [rad]
  Vec3 sigma_bias = Vec3::Zero();      ///< [rad/s]
  MekfUpdateResult update;             ///< the update of this step (empty for propagation)
};
const char* toString(MekfStep::Event e);

class AttitudeMekf {
 public:
  /// Precondition: options.isValid().
  explicit AttitudeMekf(const MekfOptions& options);

  /// Starts the filter at time t [s] with an attitude and its 3x3 body covariance; bias
  /// prior from the options unless given.
  void initialize(double t, const Quat& q_ib, const Mat3& attitude_cov,
                  const Vec3& bias = Vec3::Zero());
  void initialize(double t, const Quat& q_ib, const Vec3& bias, const Mat6& P);
  bool initialized() const { return initialized_; }
  /// Re-initialisation after the filter and the sensor disagreed: the attitude restarts from
  /// an independent fix (q_ib, 3x3 body covariance) at time t, the bias estimate and its
  /// covariance are kept, and their correlation with the old attitude error is dropped (the
  /// fix's error is independent of it). Before initialisation it is initialize().
  void resetAttitude(double t, const Quat& q_ib, const Mat3& attitude_cov);

  /// Propagates to t1 with the gyro's mean measured rate over [time(), t1] [rad/s] (gyroless:
  /// at the state's rate; the argument is not used).
  /// Returns false (filter unchanged, reason in *why) if not initialized or t1 <= time().
  bool propagate(const Vec3& gyro_rate, double t1, std::string* why = nullptr);
  /// Propagates to t without a gyro sample (a gap): holds the last measured rate.
  bool predictTo(double t, std::string* why = nullptr);
  /// The state at t without changing the filter (last measured rate held; for t < time()
  /// it extrapolates backwards with process noise of |t - time()|, conservative).
  MekfPrediction predictAt(double t) const;

  /// Attitude fix with its 3x3 body-frame covariance at the filter's current time.
  MekfUpdateResult updateAttitude(const Quat& q_meas_ib, const Mat3& cov_body);
  /// Individual stars at the current time (1 or more; at most options.max_star_vectors used).
  MekfUpdateResult updateStarVectors(const std::vector<StarVectorMeasurement>& stars);
  /// Gyroless model: a measured body rate [rad/s] with its 3x3 covariance at the current time
  /// (refused with a reason for the gyro model, whose state has no rate).
  MekfUpdateResult updateRate(const Vec3& rate_body, const Mat3& cov);
  bool gyroless() const { return opt_.model == MekfOptions::Model::kGyroless; }
  /// The body rate: the state's (gyroless), else the last gyro sample minus the bias.
  Vec3 rate() const { return gyroless() ? b_ : Vec3(last_rate_ - b_); }

  double time() const { return t_; }
  const Quat& attitude() const { return q_; }
  const Vec3& bias() const { return b_; }
  const Mat6& covariance() const { return P_; }
  Mat3 attitudeCov() const { return P_.topLeftCorner<3, 3>(); }
  /// Output of the last step (propagation or update).
  MekfStep step() const;
  int acceptedUpdates() const { return accepted_; }
  int rejectedUpdates() const { return rejected_; }
  /// Updates rejected in a row since the last accepted one or (re)initialisation. A gate
  /// alone can lock the filter out: when the prior dominates S, every later fix sees the
  /// same prior error, so navigators re-initialise after a few (resetAttitude).
  int consecutiveRejections() const { return consecutive_rejections_; }
  const MekfOptions& options() const { return opt_; }
  /// The gate threshold used for `dof` degrees of freedom.
  double gateThreshold(int dof) const;

  /// Error-state transition over dt at the bias-corrected rate w (M&C eq. 6.83).
  static Mat6 transition(const Vec3& w, double dt);
  /// Discrete process noise over dt (M&C eq. 6.93).
  static Mat6 processNoise(double sigma_v, double sigma_u, double dt);
  /// Star-vector model at attitude q for catalog direction r: the predicted body vector
  /// b_pred = R(q)^T r, the tangent basis E (2x3, rows orthonormal and across b_pred) and
  /// the attitude Jacobian H_att = E [b_pred x] of E * R(q Exp(dtheta))^T r.
  static Vec3 starVectorModel(const Quat& q_ib, const Vec3& r_i, Eigen::Matrix<double, 2, 3>* E,
                              Eigen::Matrix<double, 2, 3>* H_att);

 private:
  struct State {
    double t;
    Quat q;
    Vec3 b;
    Mat6 P;
  };
  void propagateState(State& s, const Vec3& gyro_rate, double dt) const;
  /// Gated Joseph update with the given innovation model; applies the reset.
  template <int Rows>
  void applyUpdate(const Eigen::Matrix<double, Rows, 1>& y, const Eigen::Matrix<double, Rows, 6>& H,
                   const Eigen::Matrix<double, Rows, Rows>& R, MekfUpdateResult& out);
  void record(MekfStep::Event e, const MekfUpdateResult* u);

  MekfOptions opt_;
  bool initialized_ = false;
  double t_ = 0;
  Quat q_ = Quat::Identity();
  Vec3 b_ = Vec3::Zero();
  Mat6 P_ = Mat6::Identity();
  Vec3 last_rate_ = Vec3::Zero();  ///< last gyro measurement (held through gaps)
  std::vector<double> gate_by_dof_;
  int accepted_ = 0, rejected_ = 0, consecutive_rejections_ = 0;
  MekfStep::Event last_event_ = MekfStep::Event::kInit;
  MekfUpdateResult last_update_;
};

}  // namespace st

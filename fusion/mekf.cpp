#include "fusion/mekf.hpp"

#include <Eigen/Cholesky>
#include <cmath>
#include <limits>

#include "common/conventions.hpp"
#include "fusion/consistency.hpp"
#include "fusion/gyroless_model.hpp"

namespace st {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
}

const char* toString(MekfStep::Event e) {
  switch (e) {
    case MekfStep::Event::kInit:
      return "init";
    case MekfStep::Event::kPropagate:
      return "propagate";
    case MekfStep::Event::kAttitudeFix:
      return "attitude_fix";
    case MekfStep::Event::kStarVectors:
      return "star_vectors";
    case MekfStep::Event::kRate:
      return "rate";
  }
  return "?";
}

MekfOptions MekfOptions::fromDatasheet(double arw_deg_rt_h, double rrw_deg_h_rt_h,
                                       double initial_bias_sigma_deg_h) {
  MekfOptions o;
  o.arw_rad_rt_s = gyro_units::arwToFilter(arw_deg_rt_h);
  o.rrw_rad_s_rt_s = gyro_units::rrwToFilter(rrw_deg_h_rt_h);
  o.initial_bias_sigma_rad_s = gyro_units::biasToFilter(initial_bias_sigma_deg_h);
  return o;
}

bool MekfOptions::isValid(std::string* error) const {
  auto fail = [&](const char* msg) {
    if (error) *error = msg;
    return false;
  };
  if (!(arw_rad_rt_s >= 0) || !std::isfinite(arw_rad_rt_s))
    return fail("arw_rad_rt_s must be >= 0");
  if (!(rrw_rad_s_rt_s >= 0) || !std::isfinite(rrw_rad_s_rt_s))
    return fail("rrw_rad_s_rt_s must be >= 0");
  if (!(initial_bias_sigma_rad_s >= 0) || !std::isfinite(initial_bias_sigma_rad_s))
    return fail("initial_bias_sigma_rad_s must be >= 0");
  if (!(gate_probability > 0 && gate_probability < 1))
    return fail("gate_probability must be in (0, 1)");
  if (max_star_vectors < 1 || max_star_vectors > 256)
    return fail("max_star_vectors must be in [1, 256]");
  if (!(rate_walk_rad_s2_rt_hz >= 0) || !std::isfinite(rate_walk_rad_s2_rt_hz))
    return fail("rate_walk_rad_s2_rt_hz must be >= 0");
  if (!(initial_rate_sigma_rad_s > 0) || !std::isfinite(initial_rate_sigma_rad_s))
    return fail("initial_rate_sigma_rad_s ([filter] rate_sigma_deg_s) must be > 0");
  return true;
}

StarVectorMeasurement StarVectorMeasurement::fromSigma(const Vec3& b, const Vec3& r, double sigma) {
  const Vec3 bn = b.normalized();
  return {bn, r.normalized(), sigma * sigma * (Mat3::Identity() - bn * bn.transpose())};
}

AttitudeMekf::AttitudeMekf(const MekfOptions& options) : opt_(options) {
  // Gate thresholds for every dof an update can have, computed once (a quantile costs µs).
  const int max_dof = std::max(3, 2 * opt_.max_star_vectors);
  gate_by_dof_.assign(max_dof + 1, kInf);
  if (opt_.gate_enabled)
    for (int d = 1; d <= max_dof; ++d)
      gate_by_dof_[d] = chiSquareQuantile(opt_.gate_probability, d);
}

double AttitudeMekf::gateThreshold(int dof) const {
  if (dof < 1 || dof >= static_cast<int>(gate_by_dof_.size())) return kInf;
  return gate_by_dof_[dof];
}

void AttitudeMekf::initialize(double t, const Quat& q_ib, const Mat3& attitude_cov,
                              const Vec3& bias) {
  Mat6 P = Mat6::Zero();
  P.topLeftCorner<3, 3>() = attitude_cov;
  const double s2 = gyroless() ? opt_.initial_rate_sigma_rad_s : opt_.initial_bias_sigma_rad_s;
  P.bottomRightCorner<3, 3>() = Mat3::Identity() * s2 * s2;
  initialize(t, q_ib, bias, P);
}

void AttitudeMekf::initialize(double t, const Quat& q_ib, const Vec3& bias, const Mat6& P) {
  t_ = t;
  q_ = canonical(q_ib);
  b_ = bias;
  P_ = 0.5 * (P + P.transpose());
  last_rate_ = gyroless() ? Vec3::Zero() : bias;  // gyro: no rotation until the first sample
  initialized_ = true;
  consecutive_rejections_ = 0;
  record(MekfStep::Event::kInit, nullptr);
}

void AttitudeMekf::resetAttitude(double t, const Quat& q_ib, const Mat3& attitude_cov) {
  if (!initialized_) {  // nothing learned to keep: the bias prior of the options
    initialize(t, q_ib, attitude_cov);
    return;
  }
  Mat6 P = Mat6::Zero();
  P.topLeftCorner<3, 3>() = attitude_cov;
  P.bottomRightCorner<3, 3>() = P_.bottomRightCorner<3, 3>();
  const Vec3 rate = last_rate_;
  initialize(t, q_ib, b_, P);
  last_rate_ = rate;  // the gyro's last sample still holds through a gap
}

Mat6 AttitudeMekf::transition(const Vec3& w, double dt) {
  const double n = w.norm();
  const double a = n * dt;
  const Mat3 W = skew(w);
  const Mat3 W2 = W * W;
  Mat3 Psi;
  if (a < 1e-4) {  // series of M&C eq. 6.83 for small angles (relative error < 1e-17)
    Psi = -Mat3::Identity() * dt + W * (0.5 * dt * dt) - W2 * (dt * dt * dt / 6.0);
  } else {
    Psi = W * ((1.0 - std::cos(a)) / (n * n)) - Mat3::Identity() * dt -
          W2 * ((a - std::sin(a)) / (n * n * n));
  }
  Mat6 Phi = Mat6::Identity();
  Phi.topLeftCorner<3, 3>() = quatExp(w * dt).toRotationMatrix().transpose();  // Theta
  Phi.topRightCorner<3, 3>() = Psi;
  return Phi;
}

Mat6 AttitudeMekf::processNoise(double sv, double su, double dt) {
  const double su2 = su * su;
  Mat6 Q = Mat6::Zero();
  Q.topLeftCorner<3, 3>().diagonal().setConstant(sv * sv * dt + su2 * dt * dt * dt / 3.0);
  Q.topRightCorner<3, 3>().diagonal().setConstant(-0.5 * su2 * dt * dt);
  Q.bottomLeftCorner<3, 3>().diagonal().setConstant(-0.5 * su2 * dt * dt);
  Q.bottomRightCorner<3, 3>().diagonal().setConstant(su2 * dt);
  return Q;
}

void AttitudeMekf::propagateState(State& s, const Vec3& gyro_rate, double dt) const {
  if (gyroless()) {
    const Vec3 w = s.b;  // the state's rate, held over the step (fusion/gyroless_model.hpp)
    s.q = canonical(s.q * quatExp(w * dt));
    const Mat6 Phi = gyrolessTransition(w, dt);
    const Mat6 P = Phi * s.P * Phi.transpose() + gyrolessProcessNoise(opt_.rate_walk_rad_s2_rt_hz, dt);
    s.P = 0.5 * (P + P.transpose());
    s.t += dt;
    return;
  }
  const double sv = opt_.arw_rad_rt_s, su = opt_.rrw_rad_s_rt_s;
  const Vec3 w = gyro_rate - s.b;
  s.q = s.q * quatExp(w * dt);  // exact for a constant rate over the step
  s.q = canonical(s.q);
  const Mat6 Phi = transition(w, dt);
  // Phi = [Theta Psi; 0 I]: block products cost less than a full 6x6 sandwich.
  const Mat3 Th = Phi.topLeftCorner<3, 3>(), Ps = Phi.topRightCorner<3, 3>();
  const Mat3 P11 = s.P.topLeftCorner<3, 3>(), P12 = s.P.topRightCorner<3, 3>();
  const Mat3 P22 = s.P.bottomRightCorner<3, 3>();
  const Mat3 A = Th * P11 + Ps * P12.transpose();  // first block row of Phi P
  const Mat3 B = Th * P12 + Ps * P22;
  const double adt = std::abs(dt);
  const double su2 = su * su;
  Mat3 N11 = A * Th.transpose() + B * Ps.transpose();
  N11.diagonal().array() += sv * sv * adt + su2 * adt * adt * adt / 3.0;
  Mat3 N12 = B;
  N12.diagonal().array() -= 0.5 * su2 * adt * adt;
  Mat3 N22 = P22;
  N22.diagonal().array() += su2 * adt;
  s.P.topLeftCorner<3, 3>() = 0.5 * (N11 + N11.transpose());
  s.P.topRightCorner<3, 3>() = N12;
  s.P.bottomLeftCorner<3, 3>() = N12.transpose();
  s.P.bottomRightCorner<3, 3>() = N22;
  s.t += dt;
}

bool AttitudeMekf::propagate(const Vec3& gyro_rate, double t1, std::string* why) {
  if (!initialized_) {
    if (why) *why = "filter not initialized";
    return false;
  }
  const double dt = t1 - t_;
  if (!(dt > 0)) {
    if (why) *why = "gyro sample not after the filter time (out of order or duplicate)";
    return false;
  }
  State s{t_, q_, b_, P_};
  propagateState(s, gyro_rate, dt);
  t_ = t1;  // exact, not accumulated
  q_ = s.q;
  P_ = s.P;
  if (!gyroless()) last_rate_ = gyro_rate;
  last_event_ = MekfStep::Event::kPropagate;
  return true;
}

bool AttitudeMekf::predictTo(double t, std::string* why) { return propagate(last_rate_, t, why); }

MekfPrediction AttitudeMekf::predictAt(double t) const {
  State s{t_, q_, b_, P_};
  if (initialized_ && t != t_) propagateState(s, last_rate_, t - t_);
  return {t, canonical(s.q), s.b, s.P, gyroless() ? s.b : Vec3(last_rate_ - s.b)};
}

template <int Rows>
void AttitudeMekf::applyUpdate(const Eigen::Matrix<double, Rows, 1>& y,
                               const Eigen::Matrix<double, Rows, 6>& H,
                               const Eigen::Matrix<double, Rows, Rows>& R, MekfUpdateResult& out) {
  using MatRR = Eigen::Matrix<double, Rows, Rows>;
  const Eigen::Matrix<double, 6, Rows> PHt = P_ * H.transpose();
  MatRR S = H * PHt + R;
  S = 0.5 * (S + S.transpose());
  const Eigen::LLT<MatRR> llt(S);
  out.dof = static_cast<int>(y.size());
  out.innovation = y;
  out.innovation_cov = S;
  out.gate = gateThreshold(out.dof);
  if (llt.info() != Eigen::Success) {
    out.accepted = false;
    out.reason = "innovation covariance not positive definite";
    ++rejected_;
    ++consecutive_rejections_;
    return;
  }
  out.nis = y.dot(llt.solve(y));
  if (!(out.nis <= out.gate)) {
    out.accepted = false;
    out.reason = "chi-square gate: NIS " + std::to_string(out.nis) + " > " +
                 std::to_string(out.gate) + " (" + std::to_string(out.dof) + " dof)";
    ++rejected_;
    ++consecutive_rejections_;
    return;
  }
  // K = P H^T S^-1
  const Eigen::Matrix<double, 6, Rows> K = llt.solve(PHt.transpose()).transpose();
  const Vec6 dx = K * y;
  const Mat6 IKH = Mat6::Identity() - K * H;
  const Mat6 P = IKH * P_ * IKH.transpose() + K * R * K.transpose();  // Joseph form
  P_ = 0.5 * (P + P.transpose());
  q_ = canonical(q_ * quatExp(dx.head<3>()));  // reset: the error moves into q and b
  b_ += dx.tail<3>();
  out.accepted = true;
  out.reason.clear();
  ++accepted_;
  consecutive_rejections_ = 0;
}

Vec3 AttitudeMekf::starVectorModel(const Quat& q_ib, const Vec3& r_i,
                                   Eigen::Matrix<double, 2, 3>* E,
                                   Eigen::Matrix<double, 2, 3>* H_att) {
  const Vec3 b_pred = q_ib.conjugate() * r_i.normalized();
  // Orthonormal basis of the plane across b_pred.
  const Vec3 helper = std::abs(b_pred.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  const Vec3 e1 = b_pred.cross(helper).normalized();
  const Vec3 e2 = b_pred.cross(e1);
  Eigen::Matrix<double, 2, 3> Eb;
  Eb.row(0) = e1.transpose();
  Eb.row(1) = e2.transpose();
  if (E) *E = Eb;
  // R(q Exp(d))^T r = Exp(-d) b_pred = b_pred + [b_pred x] d + O(d^2)
  if (H_att) *H_att = Eb * skew(b_pred);
  return b_pred;
}

MekfUpdateResult AttitudeMekf::updateAttitude(const Quat& q_meas_ib, const Mat3& cov_body) {
  MekfUpdateResult out;
  if (!initialized_) {
    out.reason = "filter not initialized";
    return out;
  }
  const Vec3 y = quatLog(q_.conjugate() * q_meas_ib);  // body-frame residual
  Eigen::Matrix<double, 3, 6> H = Eigen::Matrix<double, 3, 6>::Zero();
  H.leftCols<3>().setIdentity();
  applyUpdate<3>(y, H, cov_body, out);
  record(MekfStep::Event::kAttitudeFix, &out);
  return out;
}

MekfUpdateResult AttitudeMekf::updateStarVectors(const std::vector<StarVectorMeasurement>& stars) {
  MekfUpdateResult out;
  if (!initialized_) {
    out.reason = "filter not initialized";
    return out;
  }
  if (stars.empty()) {
    out.reason = "no star vectors";
    return out;
  }
  const int n = std::min<int>(static_cast<int>(stars.size()), opt_.max_star_vectors);
  Eigen::VectorXd y(2 * n);
  Eigen::Matrix<double, Eigen::Dynamic, 6> H =
      Eigen::Matrix<double, Eigen::Dynamic, 6>::Zero(2 * n, 6);
  Eigen::MatrixXd R = Eigen::MatrixXd::Zero(2 * n, 2 * n);
  for (int k = 0; k < n; ++k) {
    const StarVectorMeasurement& m = stars[k];
    Eigen::Matrix<double, 2, 3> E, Ha;
    starVectorModel(q_, m.r, &E, &Ha);
    y.segment<2>(2 * k) = E * m.b.normalized();  // E^T b_pred = 0: this is the residual
    H.block<2, 3>(2 * k, 0) = Ha;
    R.block<2, 2>(2 * k, 2 * k) = E * m.cov_b * E.transpose();
  }
  applyUpdate<Eigen::Dynamic>(y, H, R, out);
  record(MekfStep::Event::kStarVectors, &out);
  return out;
}

MekfUpdateResult AttitudeMekf::updateRate(const Vec3& rate_body, const Mat3& cov) {
  MekfUpdateResult out;
  if (!initialized_) {
    out.reason = "filter not initialized";
    return out;
  }
  if (!gyroless()) {
    out.reason = "rate update: the gyro model's state has no rate";
    return out;
  }
  const Vec3 y = rate_body - b_;
  Eigen::Matrix<double, 3, 6> H = Eigen::Matrix<double, 3, 6>::Zero();
  H.rightCols<3>().setIdentity();
  applyUpdate<3>(y, H, cov, out);
  record(MekfStep::Event::kRate, &out);
  return out;
}

void AttitudeMekf::record(MekfStep::Event e, const MekfUpdateResult* u) {
  last_event_ = e;
  if (u)
    last_update_ = *u;
  else
    last_update_ = MekfUpdateResult{};
}

MekfStep AttitudeMekf::step() const {
  MekfStep s;
  s.event = last_event_;
  s.t = t_;
  s.q_ib = q_;
  s.bias = b_;
  s.sigma_attitude = P_.diagonal().head<3>().cwiseSqrt();
  s.sigma_bias = P_.diagonal().tail<3>().cwiseSqrt();
  if (last_event_ == MekfStep::Event::kAttitudeFix || last_event_ == MekfStep::Event::kStarVectors ||
      last_event_ == MekfStep::Event::kRate)
    s.update = last_update_;
  return s;
}

}  // namespace st

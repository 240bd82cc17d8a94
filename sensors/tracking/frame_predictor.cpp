#include "sensors/tracking/frame_predictor.hpp"

#include <cmath>

namespace st {

std::optional<CameraPrediction> FramePredictor::predict(
    double t_s, const std::optional<CameraPrediction>& external,
    const std::optional<Vec3>& rate_cam, PredictionSource* source) const {
  *source = PredictionSource::kNone;
  if (external) {
    *source = PredictionSource::kExternal;
    return external;
  }
  if (!opts_.frame_to_frame || !last_) return std::nullopt;
  const double dt = t_s - last_->t_s;
  if (dt < 0 || dt > opts_.max_propagation_s) return std::nullopt;

  CameraPrediction p;
  Mat3 rate_term = Mat3::Zero();
  if (rate_cam) {
    p.rate_cam = *rate_cam;
    rate_term = std::pow(opts_.gyro_sigma * dt, 2) * Mat3::Identity();
    *source = PredictionSource::kGyro;
  } else if (prev_) {
    // Rate match (seed 004 §5.5.3): the rate of the last two attitudes, held constant.
    const double dt_prev = last_->t_s - prev_->t_s;
    if (!(dt_prev > 0) || dt_prev > opts_.max_propagation_s) return std::nullopt;
    p.rate_cam = quatLog(prev_->q_ic.conjugate() * last_->q_ic) / dt_prev;
    // Extrapolated error e = dth_last (1 + k) - dth_prev k, k = dt / dt_prev; plus a constant
    // angular acceleration over the extrapolation: alpha (dt^2 + dt dt_prev) / 2 per axis.
    const double k = dt / dt_prev;
    const double acc = 0.5 * opts_.accel_sigma * (dt * dt + dt * dt_prev);
    rate_term = (2 * k + k * k) * last_->cov_cam + k * k * prev_->cov_cam +
                acc * acc * Mat3::Identity();
    *source = PredictionSource::kRateMatch;
  } else {
    return std::nullopt;  // one attitude and no rate: lost-in-space once more
  }
  const Mat3 dR = quatExp(p.rate_cam * dt).toRotationMatrix();
  p.q_ic = canonical(last_->q_ic * quatExp(p.rate_cam * dt));
  p.cov_cam = dR.transpose() * last_->cov_cam * dR + rate_term;
  return p;
}

bool FramePredictor::correctForAcceleration(const std::optional<Vec3>& rate_cam,
                                            CameraFix& fix) const {
  if (!rate_cam || !last_rate_ || !(opts_.exposure_s > 0)) return false;
  const double dt = fix.t_s - last_rate_->t_s;
  if (!(dt > 0) || dt > opts_.max_propagation_s) return false;
  // theta(tau) = w tau + a tau^2 / 2 about mid-exposure; its mean over the exposure T is
  // a T^2 / 24, the rotation of the fix (q_ic(mean) = q_ic(mid) Exp(a T^2 / 24)). Each rate
  // carries gyro_sigma, so a has 2 gyro_sigma^2 / dt^2 per axis.
  const Vec3 accel = (*rate_cam - last_rate_->rate_cam) / dt;
  // Only an acceleration the rates resolve (3 sigma of their noise) is corrected for: below
  // that the correction would be mostly noise, and the bias it removes is below the noise
  // of the rates too.
  const double accel_sigma = std::sqrt(2.0) * opts_.gyro_sigma / dt;
  if (accel.norm() < 3.0 * accel_sigma) return false;
  const double k = opts_.exposure_s * opts_.exposure_s / 24.0;
  fix.q_ic = canonical(fix.q_ic * quatExp(-k * accel));
  fix.cov_cam += 2.0 * std::pow(k * opts_.gyro_sigma / dt, 2) * Mat3::Identity();
  return true;
}

void FramePredictor::addTrackingFix(const CameraFix& fix) {
  prev_ = last_;
  last_ = fix;
}

void FramePredictor::addLostInSpaceFix(const CameraFix& fix) {
  if (last_ && fix.t_s - last_->t_s <= opts_.max_propagation_s) {
    prev_ = last_;
  } else {
    prev_.reset();
  }
  last_ = fix;
}

void FramePredictor::recordRate(double t_s, const std::optional<Vec3>& rate_cam) {
  if (rate_cam) {
    last_rate_ = TimedRate{t_s, *rate_cam};
  } else {
    last_rate_.reset();
  }
}

void FramePredictor::reset() {
  last_.reset();
  prev_.reset();
  last_rate_.reset();
}

}  // namespace st

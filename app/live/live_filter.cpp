#include "app/live/live_filter.hpp"

#include <mrpt/obs/CObservationIMU.h>

#include <chrono>

#include "sensors/mrpt/observation_star_tracker.hpp"

namespace st::app {

LiveFilter::LiveFilter(LiveFilterOptions options)
    : opts_(std::move(options)), filter_(opts_.mekf) {}

double LiveFilter::seconds(mrpt::Clock::time_point t) const {
  // Differences of time points, never of two large doubles (MRPT-NOTES.md).
  return std::chrono::duration<double>(t - *t0_).count();
}

void LiveFilter::push(const mrpt::obs::CObservation::Ptr& obs) {
  const bool gyro = std::dynamic_pointer_cast<mrpt::obs::CObservationIMU>(obs) != nullptr;
  const bool fix = std::dynamic_pointer_cast<CObservationStarTracker>(obs) != nullptr;
  if (!gyro && !fix) return;
  std::lock_guard<std::mutex> lock(m_);
  if (!t0_) t0_ = obs->timestamp;
  buffer_.emplace(obs->timestamp, obs);
}

void LiveFilter::processUpTo(mrpt::Clock::time_point now) {
  const auto limit = now - std::chrono::duration_cast<mrpt::Clock::duration>(
                               std::chrono::duration<double>(opts_.latency_s));
  std::lock_guard<std::mutex> lock(m_);
  while (!buffer_.empty() && buffer_.begin()->first <= limit) {
    feed(*buffer_.begin()->second);
    buffer_.erase(buffer_.begin());
  }
}

void LiveFilter::flush() {
  std::lock_guard<std::mutex> lock(m_);
  for (auto& [t, o] : buffer_) feed(*o);
  buffer_.clear();
}

void LiveFilter::feed(const mrpt::obs::CObservation& obs) {
  const double t = seconds(obs.timestamp);
  if (const auto* imu = dynamic_cast<const mrpt::obs::CObservationIMU*>(&obs)) {
    using mrpt::obs::IMU_WX, mrpt::obs::IMU_WY, mrpt::obs::IMU_WZ;
    last_rate_ = Vec3(imu->get(IMU_WX), imu->get(IMU_WY), imu->get(IMU_WZ));
    ++stats_.gyro;
    if (filter_.initialized() && t > filter_.time()) filter_.propagate(last_rate_, t);
    return;
  }
  const auto* fix = dynamic_cast<const CObservationStarTracker*>(&obs);
  if (!fix || !fix->hasAttitude()) return;
  ++stats_.fixes;
  if (!filter_.initialized()) {
    filter_.initialize(t, fix->q_ib, fix->cov_body);
    return;
  }
  if (filter_.consecutiveRejections() >= opts_.reinit_after_rejections) {
    ++stats_.reinits;
    filter_.resetAttitude(t, fix->q_ib, fix->cov_body);
    return;
  }
  if (t < filter_.time()) {  // processed later than the reorder window allowed
    ++stats_.late;
    return;
  }
  if (t > filter_.time()) filter_.predictTo(t);
  const MekfUpdateResult r = filter_.updateAttitude(fix->q_ib, fix->cov_body);
  ++(r.accepted ? stats_.accepted : stats_.rejected);
}

// GCC 12 reports a false "may be used uninitialized" inside Eigen's AVX code when the filter
// (fixed-size 6x6 matrices) is copied.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
std::optional<AttitudePrediction> LiveFilter::predict(mrpt::Clock::time_point t) const {
  std::lock_guard<std::mutex> lock(m_);
  if (!filter_.initialized() || !t0_) return std::nullopt;
  // The filter lags the clock by latency_s (the reorder window), but the gyro samples in the
  // buffer are already known: propagate a copy through them so that the prediction is not an
  // extrapolation of a single noisy sample over the whole window (ARW per 100 Hz sample is
  // ~90 arcsec/s for a 0.15 deg/sqrt(h) gyro).
  // The rate handed on (the streak length, the acceleration) is the mean of the samples of
  // the last kRateWindowS: one sample carries the full white rate noise.
  constexpr double kRateWindowS = 0.1;
  AttitudeMekf ahead = filter_;
  Vec3 rate = last_rate_, rate_sum = Vec3::Zero();
  int rate_n = 0;
  const double t_s = seconds(t);
  for (const auto& [ts, o] : buffer_) {
    if (ts > t) break;
    const auto* imu = dynamic_cast<const mrpt::obs::CObservationIMU*>(o.get());
    if (!imu) continue;
    using mrpt::obs::IMU_WX, mrpt::obs::IMU_WY, mrpt::obs::IMU_WZ;
    rate = Vec3(imu->get(IMU_WX), imu->get(IMU_WY), imu->get(IMU_WZ));
    const double ti = seconds(ts);
    if (ti > ahead.time()) ahead.propagate(rate, ti);
    if (ti > t_s - kRateWindowS) {
      rate_sum += rate;
      ++rate_n;
    }
  }
  const MekfPrediction p = ahead.predictAt(t_s);
  AttitudePrediction out;
  out.q_ib = p.q_ib;
  out.cov_body = p.attitudeCov();
  out.rate_body = (rate_n > 0 ? Vec3(rate_sum / rate_n) : rate) - p.bias;
  return out;
}

#pragma GCC diagnostic pop

bool LiveFilter::current(Quat& q_ib, Mat3& P_att) const {
  std::lock_guard<std::mutex> lock(m_);
  if (!filter_.initialized()) return false;
  q_ib = filter_.attitude();
  P_att = filter_.attitudeCov();
  return true;
}

LiveFilter::Stats LiveFilter::stats() const {
  std::lock_guard<std::mutex> lock(m_);
  return stats_;
}

}  // namespace st::app

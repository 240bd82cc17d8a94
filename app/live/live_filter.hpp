/// @file live_filter.hpp
/// The real-time half of the navigator loop for `startracker live`: an AttitudeMekf fed with
/// the gyro samples (CObservationIMU) and the star tracker's fixes (CObservationStarTracker)
/// in timestamp order, whose prediction at a frame time goes back to CStarTrackerSensor (its
/// Predictor, called from the sensor's thread) for predictive centroiding and recursive ID.
///
/// st::Navigator (fusion/navigator.hpp) runs its own pipeline on CAMERA frames; here the
/// pipeline runs inside the sensor (its own thread), so the filter is separate: fixes
/// arrive after the frame's processing time, hence a reorder buffer of `latency_s`: an
/// observation enters the filter once the wall clock is latency_s past its timestamp, in
/// timestamp order. Predictions extrapolate from the filter time (last rate held).
/// A fix older than the filter time (processing took longer than latency_s) is counted as
/// late and skipped; `reinit_after_rejections` gate rejections in a row re-initialise the
/// filter from the next fix, so it never diverges silently.
#pragma once
#include <mrpt/core/Clock.h>
#include <mrpt/obs/CObservation.h>

#include <map>
#include <mutex>
#include <optional>
#include <string>

#include "fusion/mekf.hpp"
#include "sensors/tracking/frame.hpp"

namespace st::app {

struct LiveFilterOptions {
  MekfOptions mekf = MekfOptions::fromDatasheet(0.15, 0.5, 10.0);
  double latency_s = 0.5;
  int reinit_after_rejections = 3;
};

class LiveFilter {
 public:
  explicit LiveFilter(LiveFilterOptions options);

  /// Queues an observation (gyro or star-tracker fix; others are ignored).
  void push(const mrpt::obs::CObservation::Ptr& obs);
  /// Feeds the filter with the queued observations older than now - latency_s.
  void processUpTo(mrpt::Clock::time_point now);
  /// Feeds everything queued (at the end of a run).
  void flush();

  /// Thread-safe: the filter's prediction at `t`, or nothing before the first fix.
  std::optional<AttitudePrediction> predict(mrpt::Clock::time_point t) const;
  /// Thread-safe: the current estimate (false before the first fix).
  bool current(Quat& q_ib, Mat3& P_att) const;

  struct Stats {
    int gyro = 0, fixes = 0, accepted = 0, rejected = 0, late = 0, reinits = 0;
  };
  Stats stats() const;

 private:
  void feed(const mrpt::obs::CObservation& obs);
  double seconds(mrpt::Clock::time_point t) const;

  LiveFilterOptions opts_;
  mutable std::mutex m_;
  AttitudeMekf filter_;
  std::optional<mrpt::Clock::time_point> t0_;
  std::multimap<mrpt::Clock::time_point, mrpt::obs::CObservation::Ptr> buffer_;
  Vec3 last_rate_ = Vec3::Zero();
  Stats stats_;
};

}  // namespace st::app

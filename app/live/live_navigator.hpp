/// @file live_navigator.hpp
/// The live app's half of the one fusion loop: the same Navigator that `replay` runs
/// (navigation/navigator.hpp), fed with the live sensors' GYRO samples, the star tracker's
/// STAR_TRACKER fixes (the tracker runs in its sensor's thread) and the simulated camera's
/// GROUND_TRUTH, with the reorder window set to the latency a fix may have. The tracker asks
/// frameInputs() from its own thread before each frame: the loop's prediction (propagated
/// through the gyro samples already received), or lost-in-space while a re-initialisation is
/// pending. Every call is serialised by one mutex.
#pragma once
#include <mrpt/core/Clock.h>
#include <mrpt/obs/CObservation.h>

#include <memory>
#include <mutex>
#include <optional>

#include "navigation/navigator.hpp"

namespace st::app {

class LiveNavigator {
 public:
  /// The database and camera of the star tracker sensor; they must outlive this object.
  LiveNavigator(const StarDatabase& db, const CameraModel& camera, NavigatorOptions options);

  void push(const mrpt::obs::CObservation::Ptr& obs);
  void flush();
  FrameInputs frameInputs(mrpt::Clock::time_point t) const;
  /// The latest estimate (false before the first fix).
  bool current(Quat& q_ib, Mat3& P_att) const;

  struct Stats {
    int fixes = 0, accepted = 0, rejected = 0, ignored = 0, reinits = 0, warnings = 0;
  };
  Stats stats() const;
  /// Every step so far (for the summary after the run).
  std::vector<NavStep> steps() const;
  std::vector<std::string> warnings() const;

 private:
  mutable std::mutex m_;
  Navigator nav_;
  Stats stats_;
};

}  // namespace st::app

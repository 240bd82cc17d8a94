/// @file live_navigator.hpp
/// The live app's half of the one fusion loop: the same Navigator that `replay` runs
/// (navigation/navigator.hpp), fed with the live sensors' GYRO samples, the star tracker's
/// STAR_TRACKER fixes (the tracker runs in its sensor's thread) and the simulated camera's
/// GROUND_TRUTH, with the reorder window set to the latency a fix may have.
///
/// Replay's schedule: the tracker asks frameInputs() from its own thread before each frame.
/// Replay hands a frame at t the loop's state after every event before it (the gyro samples
/// up to t, the earlier frames' fixes and truths); so here the call waits until those are in
/// (the fix of the tracker's previous frame, and a gyro sample at or after t), processes
/// them (Navigator::processBefore) and only then asks the loop. A live rawlog therefore
/// replays to the same fixes (tests/app/test_live.cpp). The wait is bounded by the reorder
/// window: a gyro that stalls longer is not waited for again until it delivers, and a frame
/// asked after a timed-out wait is counted as off replay's schedule (offSchedule()).
/// Replay counts time from the rawlog's first observation: the observations are held here
/// until the tracker's first frame, then the loop starts at the earliest stamp seen (the
/// first frame's, or an earlier gyro sample's), as it will in the recording.
/// Every call is serialised by one mutex.
#pragma once
#include <mrpt/core/Clock.h>
#include <mrpt/obs/CObservation.h>

#include <condition_variable>
#include <memory>
#include <mutex>
#include <optional>
#include <vector>

#include "app/live/step_report.hpp"
#include "navigation/navigator.hpp"
#include "navigation/run_summary.hpp"

namespace st::app {

class LiveNavigator {
 public:
  /// The database and camera of the star tracker sensor; they must outlive this object.
  /// `csv_path`: the steps' CSV, written as they finish (empty: none).
  LiveNavigator(const StarDatabase& db, const CameraModel& camera, NavigatorOptions options,
                const std::string& csv_path = "");

  /// One batch as the sensors delivered it, in time order (a frame's fix and its truth come
  /// together: a waiting tracker never sees one without the other).
  void push(const std::vector<mrpt::obs::CObservation::Ptr>& batch);
  void flush();
  /// The inputs of camera head `head`'s tracker (0: the first; NavigatorOptions::
  /// head_labels order) for its frame at t, on replay's schedule (see the file comment):
  /// once every head's fix of an earlier frame it asked for is in. Heads asking for the
  /// same time wait for none of each other's fixes of that time.
  FrameInputs frameInputs(mrpt::Clock::time_point t, int head = 0);
  /// Ends every wait at once (the run is stopping and nothing more will come).
  void stopWaiting();
  /// The latest estimate (false before the first fix).
  bool current(Quat& q_ib, Mat3& P_att) const;

  struct Stats {
    int fixes = 0, accepted = 0, rejected = 0, ignored = 0, reinits = 0, warnings = 0;
    int off_schedule = 0;  ///< frames asked before everything earlier was in (timed out)
  };
  Stats stats() const;
  /// The run's navigation and integrity summaries (after flush()). No step is kept for them:
  /// they are accumulated in fixed memory, so a run of any length does not grow.
  void printSummaries(std::FILE* out) const;
  /// Closes the CSV; returns its rows (-1 without one).
  int finishCsv();
  std::vector<std::string> warnings() const;

 private:
  bool earlierEventsIn(mrpt::Clock::time_point t) const;
  /// The head whose fixes carry `label` (-1: none).
  int headOfFix(const std::string& label) const;
  void start(std::optional<mrpt::Clock::time_point> first_frame);

  mutable std::mutex m_;
  std::condition_variable arrived_;
  Navigator nav_;
  Stats stats_;
  StepReport report_;  // summaries and CSV, made as the steps finish
  std::optional<mrpt::Clock::time_point> newest_gyro_;
  struct HeadSchedule {
    std::string fix_label;
    std::optional<mrpt::Clock::time_point> newest_fix, last_asked;
  };
  std::vector<HeadSchedule> heads_;  // one per camera head
  bool gyro_stalled_ = false, stopping_ = false;
  bool started_ = false;
  std::vector<mrpt::obs::CObservation::Ptr> before_start_;
};

}  // namespace st::app

/// @file navigator.hpp
/// The MRPT edge of the one fusion loop (fusion/fusion_loop.hpp): MRPT observations from a
/// rawlog or from live sensors are decoded by the rawlog contract (labels and encodings,
/// DESIGN.md "Rawlogs") into the loop's events, and the loop's steps come back as NavSteps
/// (with the star tracker's observation for the output rawlog).
///   GYRO (CObservationIMU)              -> FusionLoop::pushGyro (a gyroless filter, [filter]
///                                          model = gyroless, does not use them);
/// A CAMERA image identical to the previous one (a stuck readout: a sensor repeats noise
/// bit for bit only when it repeats its image) is not processed: its frame fails with
/// FrameFailure::kFrozenImage (sensors/tracking/frozen_frame.hpp, the check the live sensor
/// and the library's Tracker run too); the navigator counts it and warns, and the filter
/// coasts on the gyro across it.
///   CAMERA (CObservationImage)          -> FusionLoop::pushFrame: the navigator's own star
///                                          tracker processes it with the loop's inputs
///                                          (replay; Source::kCameraFrames);
///   further heads (head_labels)         -> the same, each head with its own tracker, mounted
///                                          as its images' cameraPose says (MRPT: the pose of
///                                          the sensor on the vehicle travels with every
///                                          observation); the frames of one time stamp are one
///                                          step of the loop (a joint fix), and every head's
///                                          STAR_TRACKER observation is written
///                                          (label: sensor_label, then sensor_label_<head>);
///   STAR_TRACKER (CObservationStarTracker) -> FusionLoop::pushFix: a fix made by a sensor
///                                          that asked frameInputs() itself (live;
///                                          Source::kStarTrackerFixes);
///   VELOCITY (CObservationIMU, IMU_*_VEL)   -> FusionLoop::pushVelocity (the aberration of the
///                                          observer's own motion, corrected in every fix);
///   GROUND_TRUTH (CObservation6DFeatures) -> a marker: scored against the filter's state
///                                          there (navigation/truth_scoring.hpp), never seen
///                                          by the estimator.
/// Every policy (ordering, gaps, re-initialisation, coupling) is the loop's, so replay and
/// live behave the same; the navigator only keeps the observations until their step.
///
/// Time: seconds from the first observation pushed (`secondsFromStart`).
#pragma once
#include <mrpt/core/Clock.h>
#include <mrpt/obs/CObservation.h>
#include <mrpt/obs/CObservationImage.h>

#include <opencv2/core.hpp>

#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "catalog/star_database.hpp"
#include "fusion/fusion_loop.hpp"
#include "navigation/nav_step.hpp"
#include "sensors/camera/camera_model.hpp"
#include "sensors/mrpt/observation_star_tracker.hpp"
#include "sensors/mrpt/observation_from_frame.hpp"
#include "sensors/tracking/frozen_frame.hpp"
#include "sensors/tracking/star_tracker.hpp"

namespace st {

struct NavigatorOptions {
  PipelineOptions pipeline;  ///< the star tracker run on CAMERA frames (kCameraFrames)
  FusionOptions fusion;
  std::string camera_label = "CAMERA", gyro_label = "GYRO", truth_label = "GROUND_TRUTH";
  std::string star_tracker_label = "STAR_TRACKER";  ///< fixes read in kStarTrackerFixes
  std::string velocity_label = "VELOCITY";  ///< the observer's velocity (aberration)
  /// Camera labels of further heads beside camera_label (replay: kCameraFrames).
  std::vector<std::string> head_labels;

  bool isValid(std::string* why = nullptr) const;
};

/// The label of the fixes of a further head (camera label `camera_label`) beside the first
/// head's fixes labelled `first_fix_label`: "STAR_TRACKER_CAMERA2". Replay writes them so,
/// live reads its further CStarTrackerSensor's so.
std::string headFixLabel(const std::string& first_fix_label, const std::string& camera_label);

/// A gyro sample of the rawlog contract: a CObservationIMU labelled `o.gyro_label`. The one
/// test, for the navigator and for a caller that looks at a rawlog before replaying it.
bool isGyroObservation(const mrpt::obs::CObservation& obs, const NavigatorOptions& o);

class Navigator {
 public:
  enum class Source {
    kCameraFrames,      ///< replay: CAMERA images processed by the navigator's tracker
    kStarTrackerFixes,  ///< live: STAR_TRACKER fixes made by the sensor
  };

  /// The database and camera must outlive the navigator. Throws InputError for bad options.
  Navigator(const StarDatabase& db, const CameraModel& camera, NavigatorOptions options = {},
            Source source = Source::kCameraFrames);
  ~Navigator();
  Navigator(const Navigator&) = delete;
  Navigator& operator=(const Navigator&) = delete;

  /// Called for every finished step, with the star tracker's observations (one per head of
  /// the step; none for steps without a frame).
  using StepCallback =
      std::function<void(const NavStep&, const std::vector<CObservationStarTracker::Ptr>&)>;
  void setStepCallback(StepCallback cb) { callback_ = std::move(cb); }

  /// Queues an observation (others than the four labels are ignored).
  void push(const mrpt::obs::CObservation::Ptr& obs);
  /// Processes everything queued and finishes the last step.
  void flush();
  /// The star tracker's inputs for a frame at `t` (a live sensor asks before each frame).
  FrameInputs frameInputs(mrpt::Clock::time_point t) const;
  /// FusionLoop::processBefore at `t` (live: once everything before the frame is pushed).
  void processBefore(mrpt::Clock::time_point t);
  /// The time origin, before the first push (default: the first observation pushed). Live
  /// sets replay's, the run's earliest stamp, so that both compute the same times.
  void setTimeOrigin(mrpt::Clock::time_point t0) {
    if (!t0_) t0_ = t0;
  }

  /// Finished steps so far (kept unless keep_steps is false).
  const std::vector<NavStep>& steps() const { return steps_; }
  void setKeepSteps(bool keep) { keep_steps_ = keep; }

  /// The navigator's own warnings (unloadable frames), then the loop's.
  std::vector<std::string> warnings() const;
  int warningCount() const;
  /// Whether this run's fixes carry `label` (one of the heads' fix labels): an output rawlog
  /// writes them in place of the input's observations of that label.
  bool isFixLabel(const std::string& label) const;
  int reinitializations() const { return loop_.reinitializations(); }
  int frozenFrames() const { return frozen_frames_; }
  /// Seconds from the first observation pushed to `t` (0 before any).
  double secondsFromStart(mrpt::Clock::time_point t) const;
  const AttitudeMekf& filter() const { return loop_.filter(); }
  const FusionLoop& loop() const { return loop_; }
  const NavigatorOptions& options() const { return opts_; }

 private:
  enum Kind { kGyro, kCamera, kFix, kTruth, kVelocity, kOther };
  /// A camera head of kCameraFrames: its tracker is made at its first image (its mounting).
  struct Head {
    std::string label;      ///< camera label
    std::string fix_label;  ///< the label of its STAR_TRACKER observations
    std::unique_ptr<StarTracker> tracker;
    mrpt::poses::CPose3D mount;
    FrozenFrameCheck frozen;  // a repeated readout is not processed
    bool pose_warned = false;
  };
  Kind kindOf(const mrpt::obs::CObservation& obs, int* head = nullptr) const;
  FrameResult processFrame(uint64_t tag, double t, const FrameInputs& in);
  FrameResult processImage(Head& head, mrpt::obs::CObservationImage& io, double t,
                           const FrameInputs& in, CObservationStarTracker::Ptr& out_obs);
  Head& headOf(const mrpt::obs::CObservationImage& io, int index);
  CObservationStarTracker::Ptr observationOf(const FrameResult& r, mrpt::Clock::time_point t,
                                             const Head& head) const;
  void onStep(const FusionStep& s);
  void finishPending();
  void warn(const std::string& msg);

  const StarDatabase& db_;
  NavigatorOptions opts_;
  Source source_;
  const CameraModel& camera_;
  std::vector<Head> heads_;  // [0]: camera_label, then head_labels
  FusionLoop loop_;
  std::vector<std::string> own_warnings_;

  std::optional<mrpt::Clock::time_point> t0_;
  uint64_t next_tag_ = 0;
  std::map<uint64_t, mrpt::obs::CObservation::Ptr> held_;  // until their step
  std::map<uint64_t, int> head_of_;  // a held frame's head
  std::map<uint64_t, CObservationStarTracker::Ptr> frame_obs_;  // processed, until their step
  int frozen_frames_ = 0;

  std::optional<NavStep> pending_;  // a frame step waiting for a truth at the same time
  std::vector<CObservationStarTracker::Ptr> pending_obs_;
  std::vector<NavStep> steps_;
  bool keep_steps_ = true;
  StepCallback callback_;
};

}  // namespace st

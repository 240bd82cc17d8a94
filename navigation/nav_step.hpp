/// @file nav_step.hpp
/// One output step of the navigator: one per frame, plus one per GROUND_TRUTH time without a
/// frame (a dropped frame or an outage: the filter's prediction there). Truth fields are
/// filled by navigation/truth_scoring.hpp.
#pragma once
#include <mrpt/core/Clock.h>

#include <deque>
#include <fstream>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "common/attitude.hpp"
#include "common/output_file.hpp"
#include "fusion/fusion_loop.hpp"
#include "sensors/tracking/frame.hpp"

namespace st {

/// One camera head's frame of a step with several heads.
struct NavHead {
  std::string label;  ///< its camera label
  Mat3 R_body_cam = Mat3::Identity();
  StarTrackerMode mode = StarTrackerMode::kFailed;
  FrameFailure failure = FrameFailure::kNone;
  int stars_matched = 0;
  bool fix = false;
  Quat q_fix = Quat::Identity();  ///< body attitude of its own fix
  Mat3 cov_fix = Mat3::Zero();
  /// Its fix against truth in its own camera frame: cross-boresight and roll about its own
  /// boresight (fix && has_truth).
  AttitudeError fix_error;
  int misidentified = 0;
};

struct NavStep {
  mrpt::Clock::time_point stamp;
  double t = 0;              ///< [s] from the first observation
  bool has_frame = false;    ///< a frame (or a fix) was processed
  StarTrackerMode mode = StarTrackerMode::kFailed;  ///< the tracker's mode (has_frame only)
  FrameFailure failure = FrameFailure::kNone;
  std::string reason;        ///< the tracker's detail / the filter's rejection reason
  int stars_matched = 0;
  double frame_time_s = 0;   ///< wall time of the tracker
  bool fix = false;          ///< the tracker produced an attitude
  Quat q_fix = Quat::Identity();
  Mat3 cov_fix = Mat3::Zero();

  bool initialized = false;    ///< the filter holds a state (false before the first fix)
  bool reinitialized = false;  ///< the filter was (re-)initialised from this frame's fix
  Quat q_ib = Quat::Identity();
  Vec3 bias = Vec3::Zero();        ///< [rad/s]
  Mat3 P_att = Mat3::Zero();       ///< [rad^2] body frame
  Vec3 sigma_att = Vec3::Zero();   ///< [rad] 1-sigma per body axis
  Vec3 sigma_bias = Vec3::Zero();  ///< [rad/s]

  bool gyroless = false;           ///< the filter's state holds the rate (no gyro)
  Vec3 rate = Vec3::Zero();        ///< [rad/s] the filter's body rate (initialized)
  Vec3 sigma_rate = Vec3::Zero();  ///< [rad/s] its 1-sigma per axis (gyroless only)
  bool has_fix_rate = false;       ///< the tracker measured the rate since its last fix
  Vec3 fix_rate = Vec3::Zero();    ///< [rad/s] that rate (seed 004 eq. 7.1)
  Mat3 fix_rate_cov = Mat3::Zero();

  /// Several heads: each head's frame ([0] the camera_label head), whether their fixes were
  /// merged into the step's fix (q_fix: the joint fix), and their disagreement chi2 / dof.
  std::vector<NavHead> heads;
  bool heads_merged = false;
  double heads_chi2 = 0;
  int heads_dof = 0;

  FixUse use = FixUse::kNoFix;     ///< what the filter did with the fix
  Eigen::VectorXd innovation;
  Eigen::MatrixXd innovation_cov;
  double nis = 0;
  int nis_dof = 0;

  bool has_truth = false;
  Quat q_true = Quat::Identity();
  AttitudeError error;          ///< filter estimate vs truth
  double nees = 0;              ///< attitude NEES, 3 dof
  AttitudeError fix_error;      ///< raw fix vs truth (fix && has_truth)
  double fix_nees = 0;          ///< raw fix NEES with its own covariance, 3 dof
  /// Matched stars whose identity the truth's star list contradicts: the claimed star is
  /// not in the frame, or another true star lies nearer to the centroid and is resolved
  /// from it (fix && the truth lists stars).
  int misidentified = 0;
  /// Matched stars named after one member of an unresolved pair (< 2 PSF sigma apart) while
  /// the other member is nearer to the centroid: one image peak, either name is right.
  int blend_claims = 0;
  /// The identities were scored (the truth lists the frame's stars; a truth of the motion
  /// alone, e.g. from a simulated gyro beside a folder of frames, cannot score them).
  bool ids_scored = false;
  /// The true body rate at t: central difference of the neighbouring GROUND_TRUTH attitudes
  /// (TruthRateStream), and the filter's error against it (initialized && has_true_rate).
  bool has_true_rate = false;
  Vec3 rate_true = Vec3::Zero();
  Vec3 rate_error = Vec3::Zero();      ///< filter rate - truth [rad/s]
  double rate_nees = 0;                ///< gyroless: 3 dof, with the filter's rate covariance
  Mat3 P_rate = Mat3::Zero();
};

/// The true rate of the steps as they come (replay and live): at every step with truth whose
/// neighbours (previous and next step with truth, within max_gap_s) have truth too,
/// Log(q_prev^-1 q_next) / (t_next - t_prev), the mean rate over the two intervals (exact at
/// t for a rate constant or changing linearly). A step with truth is held until the next step
/// with truth gives its true rate, the steps after it with it; each step goes to the sink
/// once final, in order. At most one truth interval is held.
class TruthRateStream {
 public:
  using Sink = std::function<void(const NavStep&)>;
  explicit TruthRateStream(double max_gap_s = 1.0) : max_gap_s_(max_gap_s) {}
  void push(NavStep s, const Sink& out);
  /// Releases what is held (the last step with truth has no true rate).
  void flush(const Sink& out);

 private:
  double max_gap_s_;
  std::optional<NavStep> prev_truth_;
  std::deque<NavStep> held_;  // the last step with truth, then the steps after it
};

/// Copies a filter state into a step (attitude, bias, covariance, 1-sigma per axis).
void fillFilterState(NavStep& s, const FilterState& f);

/// CSV of the steps: header line and one row (t in seconds from the first observation). An
/// absent value is `nan`: the filter's columns (attitude, bias, sigmas, err_*, nees) while the
/// filter holds no state, which is every row of a run without a filter (no gyro); the raw
/// fix's columns (fix_*) on a frame without a fix or, for errors, without truth.
std::string navStepCsvHeader();
std::string navStepCsvRow(const NavStep& s);
/// The CSV written as the steps come (live): the header at once, one row per step with a
/// frame. Throws InputError naming the file when it cannot be written.
class NavStepCsvWriter {
 public:
  explicit NavStepCsvWriter(const std::string& path);
  void write(const NavStep& s);
  /// Flushes, checks and closes the stream and gives the file its real name; returns the
  /// rows written. Without it (an error, an interruption) the CSV is not left half-written.
  int finish();

 private:
  std::string path_;
  PendingOutput out_;  ///< under its real name only once finish() succeeds
  std::ofstream f_;
  int rows_ = 0;
};

}  // namespace st

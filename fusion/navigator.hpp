/// @file navigator.hpp
/// The navigator closes the loop of DESIGN.md's data flow: it owns one StarTracker
/// and one AttitudeMekf and routes observations (from a rawlog or live sensors) in timestamp
/// order:
///   GYRO (CObservationIMU)          -> AttitudeMekf::propagate (mean rate over the sample);
///   CAMERA (CObservationImage)      -> predictAt(frame time) -> FrameInputs ->
///                                      StarTracker::process -> updateAttitude (or star vectors);
///                                      the first lost-in-space fix initialises the filter;
///   GROUND_TRUTH (CObservation6DFeatures) -> statistics only, never seen by the estimator.
///
/// Robustness (issue 8):
///  - a small reorder buffer (reorder_window_s) sorts observations by (time, GYRO < CAMERA <
///    GROUND_TRUTH); an observation older than what was already processed, or an exact
///    duplicate (same label and time), is dropped with a warning naming its timestamp;
///  - gyro gaps: the filter coasts (the mean of the last 10 rates held, with the covariance of
///    a held rate error added to the process noise) through the gap, at each frame inside it
///    and up to the next sample's own interval;
///  - camera outages / dropped frames: the filter keeps propagating with the gyro, its
///    covariance grows, and the grown covariance sizes the pipeline's windows when frames
///    return, so tracking resumes without lost-in-space while the prediction is good;
///  - disagreement: after `reinit_after_rejections` fixes in a row rejected by the filter's
///    chi-square gate, the filter is re-initialised from the next lost-in-space fix (the
///    pipeline is reset so that the next frame runs lost-in-space; a fix that already is
///    lost-in-space re-initialises at once). The bias estimate is kept.
///
/// Time: seconds from the first observation pushed (`t0()`), as double; the navigator never
/// subtracts two large Unix times.
#pragma once
#include <mrpt/core/Clock.h>
#include <mrpt/obs/CObservation.h>

#include <array>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "catalog/star_database.hpp"
#include "common/attitude.hpp"
#include "fusion/mekf.hpp"
#include "sensors/camera/camera_model.hpp"
#include "sensors/mrpt/observation_star_tracker.hpp"
#include "sensors/mrpt/observation_from_frame.hpp"
#include "sensors/tracking/star_tracker.hpp"

namespace mrpt::config {
class CConfigFileBase;
}

namespace st {

struct NavigatorOptions {
  PipelineOptions pipeline;
  MekfOptions filter = MekfOptions::fromDatasheet(0.15, 0.5, 10.0);
  /// How fixes enter the filter: "attitude" (the fix with its 3x3 covariance) or "stars"
  /// (tight coupling: each matched star's unit vector; sigma from the fix covariance).
  std::string update = "attitude";
  int reinit_after_rejections = 3;  ///< consecutive gate rejections -> re-initialise
  double reorder_window_s = 0.05;   ///< observations are held this long to be sorted
  /// A gap between gyro samples longer than this many nominal intervals is reported and
  /// coasted through (predictTo) instead of integrated with the next sample.
  double gyro_gap_factor = 2.5;
  std::string camera_label = "CAMERA", gyro_label = "GYRO", truth_label = "GROUND_TRUTH";
  int max_warnings = 50;  ///< warnings kept (later ones are only counted)

  /// Throws InputError naming the option when a value is unusable.
  void validate() const;
};

/// Where the star database comes from (tracker.ini [database]).
struct DatabaseSource {
  std::string path;               ///< a saved database (StarDatabase::save); empty = build
  std::string catalog;            ///< catalog for the in-memory build; empty = default
  double mag_limit = 6.5;         ///< in-memory build
  double epoch_jyear = 0;         ///< 0 = the epoch of the data (first timestamp)
  bool aberration = true;
};

/// tracker.ini, every section optional:
///   [filter]    arw_deg_rt_h, rrw_deg_h_rt_h, bias_sigma_deg_h (gyro datasheet numbers),
///               gate_probability, gate (true/false), update = attitude | stars
///   [navigator] reinit_after_rejections, reorder_window_s, gyro_gap_factor,
///               camera_label, gyro_label, truth_label
///   [pipeline]  the keys of sensors/mrpt/pipeline_ini.hpp (PipelineOptions, same names),
///               as in a CStarTrackerSensor section
///   [database]  path, catalog, mag_limit, epoch_jyear, aberration
///   [camera]    CameraModel::loadIni keys; present = overrides the rawlog's camera
/// Unknown keys in these sections are errors (a typo must not silently keep a default).
/// Relative paths are relative to the .ini's folder.
struct TrackerConfig {
  NavigatorOptions nav;
  DatabaseSource database;
  std::optional<CameraModel> camera;
  std::string source;  ///< file name for messages

  /// Throws InputError naming the file, section and key.
  static TrackerConfig load(const std::string& path);
  static TrackerConfig fromConfig(const mrpt::config::CConfigFileBase& cfg,
                                  const std::string& source, const std::string& base_dir = ".");
};

/// Builds (or loads) the database of `src` for a camera; `data_epoch_jyear` is used when the
/// source gives none. Throws InputError naming the file for a bad database/catalog.
StarDatabase makeDatabase(const DatabaseSource& src, const CameraModel& camera,
                          double data_epoch_jyear);

/// One output step: one per CAMERA frame, plus one per GROUND_TRUTH time without a frame
/// (a dropped frame or an outage: the filter's prediction there).
struct NavStep {
  mrpt::Clock::time_point stamp;
  double t = 0;              ///< [s] from Navigator::t0()
  bool has_frame = false;    ///< a CAMERA frame was processed
  StarTrackerMode mode = StarTrackerMode::kFailed;  ///< sensor mode (has_frame only)
  std::string reason;        ///< the sensor's reason / the filter's rejection reason
  int stars_matched = 0;
  double frame_time_s = 0;   ///< wall time of pipeline.process
  bool fix = false;          ///< the sensor produced an attitude
  Quat q_fix = Quat::Identity();
  Mat3 cov_fix = Mat3::Zero();

  bool initialized = false;  ///< the filter holds a state (false before the first fix)
  bool reinitialized = false;  ///< the filter was (re-)initialised from this frame's fix
  Quat q_ib = Quat::Identity();
  Vec3 bias = Vec3::Zero();    ///< [rad/s]
  Mat3 P_att = Mat3::Zero();   ///< [rad^2] body frame
  Vec3 sigma_att = Vec3::Zero();   ///< [rad] 1-sigma per body axis
  Vec3 sigma_bias = Vec3::Zero();  ///< [rad/s]

  /// "none", "accepted", "rejected"
  std::string update = "none";
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
};

/// CSV of the steps: header line and one row (t in seconds from t0).
std::string navStepCsvHeader();
std::string navStepCsvRow(const NavStep& s);

class Navigator {
 public:
  /// The database and camera must outlive the navigator. Throws InputError for bad options.
  Navigator(const StarDatabase& db, const CameraModel& camera, NavigatorOptions options = {});
  ~Navigator();
  Navigator(const Navigator&) = delete;
  Navigator& operator=(const Navigator&) = delete;

  /// Called for every finished step, with the sensor's observation (nullptr for steps
  /// without a frame).
  using StepCallback = std::function<void(const NavStep&, const CObservationStarTracker::Ptr&)>;
  void setStepCallback(StepCallback cb) { callback_ = std::move(cb); }

  /// Queues an observation; processes what is older than the reorder window.
  void push(const mrpt::obs::CObservation::Ptr& obs);
  /// Processes everything queued and finishes the last step.
  void flush();

  /// Finished steps so far (kept unless keep_steps is false).
  const std::vector<NavStep>& steps() const { return steps_; }
  void setKeepSteps(bool keep) { keep_steps_ = keep; }

  const std::vector<std::string>& warnings() const { return warnings_; }
  int warningCount() const { return warning_count_; }
  int reinitializations() const { return reinits_; }
  /// Seconds from the first observation pushed to `t` (0 before any).
  double secondsFromStart(mrpt::Clock::time_point t) const;
  const AttitudeMekf& filter() const { return filter_; }
  const StarTracker& pipeline() const { return *pipeline_; }
  const NavigatorOptions& options() const { return opts_; }

 private:
  struct Item;
  void process(const mrpt::obs::CObservation::Ptr& obs, int kind);
  void onGyro(const mrpt::obs::CObservation& obs, double t);
  void onCamera(const mrpt::obs::CObservation& obs, double t);
  void onTruth(const mrpt::obs::CObservation& obs, double t);
  void finishPending();
  void fillFilterState(NavStep& s, double t) const;
  /// Propagates the filter to t without gyro samples (see navigator.cpp).
  void coastTo(double t);
  Vec3 recentMeanRate() const;
  bool gyroStale(double t) const;
  void initializeFrom(const CObservationStarTracker& fix, double t);
  MekfUpdateResult update(const CObservationStarTracker& fix);
  void warn(const std::string& msg);
  int kindOf(const mrpt::obs::CObservation& obs) const;

  const StarDatabase& db_;
  NavigatorOptions opts_;
  std::unique_ptr<StarTracker> pipeline_;
  AttitudeMekf filter_;
  std::vector<uint32_t> id_to_index_keys_;  // sorted catalog ids
  std::vector<uint32_t> id_to_index_vals_;

  std::optional<mrpt::Clock::time_point> t0_;
  std::vector<Item> queue_;  // heap ordered by (time, kind)
  uint64_t seq_ = 0;
  std::optional<std::pair<mrpt::Clock::time_point, int>> last_processed_;
  double newest_t_ = -1e300;

  std::optional<double> last_gyro_t_;
  double gyro_dt_nominal_ = 0;
  std::array<Vec3, 10> recent_rates_{};  // ring of the last gyro rates (coasting)
  std::size_t recent_next_ = 0;
  bool in_gap_ = false;
  bool reinit_pending_ = false;
  int reinits_ = 0;

  std::optional<NavStep> pending_;
  CObservationStarTracker::Ptr pending_obs_;
  std::vector<NavStep> steps_;
  bool keep_steps_ = true;
  StepCallback callback_;
  std::vector<std::string> warnings_;
  int warning_count_ = 0;
};

}  // namespace st

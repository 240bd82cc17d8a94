/// @file fusion_loop.hpp
/// The one attitude-fusion loop (DESIGN.md data flow), MRPT-free. Replay, the live app and
/// the Monte Carlo consistency tests all drive this class; MRPT adapters (fusion/mrpt/) only
/// decode observations into its events. It owns one AttitudeMekf and decides, for every
/// event in timestamp order:
///   gyro sample    -> mounting rotation, non-finite samples dropped, gaps coasted through,
///                     propagate;
///   frame          -> the tracker's inputs (the filter's prediction at the frame time, or the
///                     gyro rate before the filter has an attitude, or "lost-in-space" while a
///                     re-initialisation is pending) -> the FrameProcessor -> the fix;
///   fix            -> a frame processed elsewhere (the live sensor's thread asked
///                     frameInputs() itself) -> the same update as a frame's fix;
///   marker         -> a step with the filter's state at that time (e.g. a truth time).
///
/// Policies, one place for all callers:
///  - ordering: events are held for `reorder_window_s` past the newest event time and taken
///    in (time, kind) order, kind gyro < frame/fix < marker; an event older than what was
///    already processed, or a duplicate (same time and kind), is dropped with a warning. Live
///    fixes arrive after their processing time: their window is the latency allowed;
///  - gyro health (fusion/gyro_health.hpp): every sample is checked in the gyro's frame
///    against its datasheet noise; a spike is replaced by the median of the samples before it;
///    an axis found stuck or noisy makes the gyro unhealthy: the filter is suspended as for a
///    lost gyro (no state reported, frames lost-in-space, fixes unfiltered) until the samples
///    pass again, then re-initialised from a lost-in-space fix (keeping the bias);
///  - camera clock: a frame (or fix) stamped later than the newest gyro sample by more than
///    the reorder window plus gyro_gap_factor sample intervals, while the gyro sent samples
///    since the previous frame (it is not silent), cannot have been taken yet when it
///    arrives (events arrive in time order, a fix after its processing): the
///    camera's clock has jumped against the gyro's. The frame is not processed: its step
///    reports FixUse::kClockRefused with no filter state at that stamp;
///  - gyro gaps: a sample later than gyro_gap_factor nominal intervals after the previous one
///    is coasted to (the mean rate of the last rate_window_s held, with the covariance of a
///    held rate error added), frames inside a gap coast too;
///  - the rate handed to a tracker is the mean gyro rate over the last rate_window_s before
///    the frame minus the bias estimate;
///  - the first fix initialises the filter; after reinit_after_rejections fixes in a row
///    refused by the filter's gate the loop asks the tracker for lost-in-space
///    (FrameInputs::force_lost_in_space) and re-initialises the attitude from the next
///    lost-in-space fix, keeping the bias (AttitudeMekf::resetAttitude). Tracking fixes made
///    before that request was seen are not used;
///  - observer velocity: the newest velocity sample up to a frame (no older than
///    max_velocity_age_s) goes to its tracker (FrameInputs::observer_velocity_km_s), and the
///    star-vector updates aberrate their catalog directions with it;
///  - updates: the fix with its covariance, or (tight coupling) each matched star's vector;
///  - several camera heads (pushFrame / pushFix with a head index): the frames of one time
///    stamp are one step. Every head's tracker gets the same inputs; the heads' fixes become
///    one joint fix (sensors/attitude/joint_fix.hpp: the joint Wahba solution of all their
///    stars, in the body frame) when their disagreement passes chi2(3 (heads - 1)) at
///    head_consistency_alpha, and that is the update. Heads that disagree are not merged:
///    with a filter each fix goes through its gate on its own (the wrong head is refused),
///    without one the step has no fix (no arbiter: nothing wrong reported as valid). A head's
///    frame that arrives after its time stamp's step was taken is dropped with a warning;
///  - gyroless (filter.model kGyroless, fusion/gyroless_model.hpp): the filter's state holds
///    the body rate and propagates itself between frames; gyro samples are not used (one
///    warning). Its prediction (attitude, covariance, rate) is handed to the tracker as the
///    gyro path's is, so the frame after the first fix already tracks. A re-initialisation
///    restarts the rate too (a rate gone wrong is what made the fixes disagree): from the
///    fix's own frame-to-frame rate (FrameResult::rate) when it has one, else from zero with
///    the prior sigma. The tracker's rate is not fed as an update (gyroless_model.hpp: it
///    shares the fixes' noise);
///  - no filter (filter_enabled false, a run without gyro) or a gyro silent for longer than
///    max_gyro_coast_s: every frame lost-in-space, the fixes pass through unfiltered (a
///    suspended filter reports no state until it is re-initialised after the gyro returns).
///
/// Time: seconds as double on the caller's scale (seconds from the first observation of a
/// run). Not thread-safe: the live adapter serialises calls.
#pragma once
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "common/chi_square.hpp"
#include "fusion/gyro_health.hpp"
#include "fusion/mekf.hpp"
#include "sensors/tracking/frame.hpp"

namespace st {

struct FusionOptions {
  MekfOptions filter = MekfOptions::fromDatasheet(0.15, 0.5, 10.0);
  enum class Update : uint8_t { kAttitude, kStarVectors };
  Update update = Update::kAttitude;  ///< how fixes enter the filter
  int reinit_after_rejections = 3;    ///< gate rejections in a row -> re-initialise
  double reorder_window_s = 0.05;     ///< events are held this long to be sorted
  /// A gyro interval longer than this many nominal intervals is a gap (coasted through).
  double gyro_gap_factor = 2.5;
  /// [s] A gyro silent longer than this before a frame has stopped, not paused: coasting
  /// holds the last rate, and a body that turns away from it leaves the filter's covariance
  /// behind (the tour's jitter: 8 deg off after 60 s). The filter is suspended: every frame
  /// lost-in-space, its fix unfiltered, until gyro samples return and a lost-in-space fix
  /// re-initialises the attitude (keeping the bias).
  double max_gyro_coast_s = 1.0;
  double rate_window_s = 0.1;         ///< [s] gyro samples averaged for the rate handed on
  Mat3 R_body_gyro = Mat3::Identity();    ///< mounting of the gyro: w_body = R w_gyro
  int max_warnings = 50;              ///< warnings kept (later ones are only counted)
  /// false: no filter at all (a run without gyro: nothing propagates the attitude between
  /// frames, and a filter fed fixes alone diverges on a moving body). Every frame is asked
  /// for lost-in-space and its fix is the output, unfiltered (FixUse::kUnfiltered).
  bool filter_enabled = true;
  GyroHealthOptions gyro_health;
  /// Refuse frames stamped ahead of the gyro's timeline (see the policy above).
  bool check_camera_clock = true;
  /// Use the observer's velocity samples (pushVelocity): every frame's tracker corrects its
  /// fix for their aberration, star-vector updates use the apparent directions.
  bool velocity_aberration = true;
  /// [s] the newest velocity sample at most this old at a frame is its velocity; an older
  /// one leaves the frame uncorrected (a warning). An orbit turns 0.07 deg/s: 10 s of hold
  /// moves its aberration by 0.06".
  double max_velocity_age_s = 10;
  /// False-alarm probability of the heads' disagreement test (several heads): heads whose
  /// fixes disagree beyond chi2(3 (heads - 1)) at it are not merged.
  double head_consistency_alpha = 1e-6;

  bool isValid(std::string* why = nullptr) const;
};
/// "attitude" | "stars".
const char* toString(FusionOptions::Update u);
/// "t = 12.345678 s": how every warning of the loop and its adapters names a time.
std::string formatLoopTime(double t_s);

/// The filter's state at a time, after any update there.
struct FilterState {
  bool initialized = false;
  bool gyroless = false;     ///< the second state block is the rate, not the bias
  Quat q_ib = Quat::Identity();
  Vec3 bias = Vec3::Zero();  ///< [rad/s] gyro bias (zero when gyroless)
  Vec3 rate = Vec3::Zero();  ///< [rad/s] body rate: the state's (gyroless), else gyro - bias
  Mat6 P = Mat6::Zero();     ///< [dtheta; db] or, gyroless, [dtheta; dw]
  Mat3 attitudeCov() const { return P.topLeftCorner<3, 3>(); }
};

/// What the loop did with a fix.
enum class FixUse : uint8_t {
  kNoFix,          ///< the frame gave no attitude
  kInitialized,    ///< the filter started from it
  kReinitialized,  ///< the attitude restarted from it (lost-in-space after rejections)
  kAccepted,       ///< filter update accepted
  kRejected,       ///< refused by the filter's gate
  kIgnored,        ///< a re-initialisation was pending and the fix was not lost-in-space
  kUnfiltered,     ///< no filter (FusionOptions::filter_enabled false), or a gyro lost or
                   ///< unhealthy: the fix is the output
  kClockRefused,   ///< the frame's stamp is ahead of the gyro's timeline: not processed
};
const char* toString(FixUse u);

/// One head's frame of a step (valid during the callback only).
struct HeadFrame {
  uint64_t tag = 0;  ///< the caller's id of the frame
  int head = 0;      ///< the head index given to pushFrame / pushFix
  const FrameResult* frame = nullptr;
};

/// One output step: a frame (or fix), the frames of several heads at one time, or a marker.
struct FusionStep {
  double t = 0;
  uint64_t tag = 0;             ///< the caller's id of the frame / marker (the first head's)
  bool is_frame = false;
  /// is_frame: the fix the filter used (a joint fix of several heads, or the one frame);
  /// valid during the callback only.
  const FrameResult* frame = nullptr;
  std::vector<HeadFrame> heads;  ///< is_frame: every head's frame of this time (>= 1)
  /// Several heads with a fix: their disagreement chi2 and its dof (joint_fix.hpp), and
  /// whether they were merged into `frame`.
  double heads_chi2 = 0;
  int heads_dof = 0;
  bool heads_merged = false;
  FixUse use = FixUse::kNoFix;
  MekfUpdateResult update;      ///< kAccepted / kRejected: the innovation record
  FilterState filter;
};

class FusionLoop {
 public:
  /// Processes a frame due at `t` with the loop's inputs (replay: the tracker runs here).
  using FrameProcessor = std::function<FrameResult(uint64_t tag, double t, const FrameInputs&)>;
  using StepCallback = std::function<void(const FusionStep&)>;
  /// Inertial unit vector of a catalog star (star-vector updates); nothing if unknown.
  using StarDirection = std::function<std::optional<Vec3>(uint32_t catalog_id)>;

  /// Throws InputError (naming the option) for invalid options.
  explicit FusionLoop(FusionOptions options, StarDirection star_direction = {});

  void setFrameProcessor(FrameProcessor p) { processor_ = std::move(p); }
  void setStepCallback(StepCallback cb) { callback_ = std::move(cb); }

  /// Rate [rad/s] in the gyro frame: the mean over the interval ending at t.
  void pushGyro(double t, const Vec3& rate_gyro);
  /// The observer's velocity [km/s] in the inertial frame at t (see velocity_aberration).
  void pushVelocity(double t, const Vec3& velocity_km_s);
  /// A frame of camera head `head` to process with the FrameProcessor when it is due.
  void pushFrame(double t, uint64_t tag, int head = 0);
  /// A frame already processed (its tracker asked frameInputs() itself).
  void pushFix(double t, uint64_t tag, FrameResult fix, int head = 0);
  /// A step with the filter's state at t.
  void pushMarker(double t, uint64_t tag);
  /// Processes everything queued.
  void flush();
  /// Processes the queued events a frame at t comes after (gyro samples up to t included),
  /// whatever the reorder window: a live tracker that knows they are all in then gets the
  /// inputs replay computes for the frame (frameInputs after exactly those events).
  void processBefore(double t);

  /// The tracker's inputs for a frame at t: the filter propagated through the gyro samples
  /// already known (also those still held for ordering); the filter itself is unchanged.
  FrameInputs frameInputs(double t) const;

  const AttitudeMekf& filter() const { return filter_; }
  const FusionOptions& options() const { return opts_; }
  const std::vector<std::string>& warnings() const { return warnings_; }
  int warningCount() const { return warning_count_; }
  int reinitializations() const { return reinits_; }
  bool reinitPending() const { return reinit_pending_; }
  /// False while a gyro health check holds the gyro for faulty (the filter is suspended).
  bool gyroHealthy() const { return !gyro_unhealthy_; }
  int gyroSpikes() const { return health_.spikes(); }
  int clockRefusedFrames() const { return clock_refused_; }
  bool gyroless() const { return filter_.gyroless(); }

 private:
  enum Kind : int { kGyro = 0, kVelocity = 1, kFrame = 2, kMarker = 3 };
  struct Event {
    double t;
    int kind;
    uint64_t seq, tag;
    Vec3 rate;                        // kGyro (body frame); kVelocity [km/s]
    std::optional<FrameResult> fix;   // kFrame made elsewhere
    std::string refused;              // kFrame: why it is not processed (camera clock)
    int head = 0;                     // kFrame: the camera head
    bool operator<(const Event& o) const;  // heap order: later is "less"
  };
  struct TimedRate {
    double t;
    Vec3 rate;
  };

  void push(Event e);
  /// Processes queued events in order while `ready(next event)` holds.
  template <class Predicate>
  void processWhile(Predicate ready);
  void process(Event& e);
  void onGyro(double t, const Vec3& rate_body);
  /// The health checks on a sample (body frame; spikes replaced in place).
  void checkHealth(double t, double dt, Vec3& rate_body);
  bool clockAhead(Event& e) const;
  void refuseFrame(Event& e);
  /// The frames of one time stamp (one per head).
  void onFrames(std::vector<Event>& group);
  /// Several heads' fixes: one joint fix, or one by one through the gate (FusionStep).
  void useHeads(double t, const std::vector<HeadFrame>& heads, FusionStep& s, FrameResult& joint);
  FixUse useFix(double t, const FrameResult& fix, MekfUpdateResult& u);
  /// (Re-)initialises the filter from a fix (gyroless: the rate from the fix's own rate).
  void initializeFrom(double t, const FrameResult& fix);
  MekfUpdateResult update(double t, const FrameResult& fix);
  void coastTo(double t);
  bool gyroStale(double t) const;
  bool gyroLost(double t) const;
  /// The velocity for a frame at t: the newest sample up to t, processed or still held.
  std::optional<Vec3> velocityAt(double t) const;
  Vec3 meanRate(double t, const std::vector<TimedRate>& extra) const;
  FilterState stateAt(double t) const;
  void emit(FusionStep& s);
  void warn(const std::string& msg);

  FusionOptions opts_;
  StarDirection star_direction_;
  FrameProcessor processor_;
  StepCallback callback_;
  AttitudeMekf filter_;

  std::vector<Event> queue_;  // heap
  uint64_t seq_ = 0;
  double newest_t_ = -1e300;
  std::optional<std::pair<double, int>> last_processed_;

  std::optional<double> last_gyro_t_;
  double gyro_dt_nominal_ = 0;
  std::vector<TimedRate> recent_;  // ring of the last gyro rates (body frame)
  mutable std::vector<TimedRate> ahead_;  // frameInputs' scratch: gyro samples still held
  std::size_t recent_next_ = 0;
  bool in_gap_ = false;
  bool gyro_lost_ = false;         // silent beyond max_gyro_coast_s: no filtering
  bool gyro_unhealthy_ = false;    // a health check failed: no filtering
  GyroHealth health_;
  std::optional<double> newest_gyro_t_;  // the gyro's timeline as pushed
  int clock_refused_ = 0;
  int gyro_ignored_ = 0;  // samples of a gyroless run
  std::vector<std::pair<double, Vec3>> velocities_;  // the last velocity samples processed
  int velocity_ignored_ = 0;
  mutable bool velocity_stale_warned_ = false;
  int gyro_since_frame_ = 0;  // gyro samples pushed since the last frame (arrival order)
  bool filter_suspended_ = false;  // since the gyro was lost, until re-initialised
  bool reinit_pending_ = false;
  int reinits_ = 0;
  ChiSquareThresholds head_threshold_;  // the heads' disagreement, by dof
  std::vector<Event> group_;            // scratch: the frames of one time stamp
  std::vector<FrameResult> made_;       // scratch: their results
  std::vector<std::string> warnings_;
  int warning_count_ = 0;
};

}  // namespace st

#include "fusion/fusion_loop.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "common/aberration.hpp"
#include "common/check.hpp"
#include "common/conventions.hpp"
#include "common/errors.hpp"
#include "sensors/attitude/joint_fix.hpp"

namespace st {

namespace {

constexpr std::size_t kRateRing = 256;  // gyro samples kept for the mean rate (>= 1 kHz x 0.1 s)
constexpr int kMaxHeads = 16;  // heads of one time stamp merged (more are used one by one)

bool isRotation(const Mat3& R) {
  return (R * R.transpose() - Mat3::Identity()).norm() < 1e-9 && R.determinant() > 0;
}

}  // namespace

bool FusionOptions::isValid(std::string* why) const {
  auto bad = [&](const std::string& key, const std::string& msg) {
    if (why) *why = "'" + key + "': " + msg;
    return false;
  };
  std::string err;
  if (!filter.isValid(&err)) return bad("filter", err);
  if (reinit_after_rejections < 1) return bad("reinit_after_rejections", "must be >= 1");
  if (!(reorder_window_s >= 0)) return bad("reorder_window_s", "must be >= 0");
  if (!(gyro_gap_factor > 1)) return bad("gyro_gap_factor", "must be > 1");
  if (!(max_gyro_coast_s > 0)) return bad("max_gyro_coast_s", "must be > 0");
  if (!(rate_window_s > 0)) return bad("rate_window_s", "must be > 0");
  if (!isRotation(R_body_gyro)) return bad("R_body_gyro", "not a rotation matrix");
  if (max_warnings < 0) return bad("max_warnings", "must be >= 0");
  if (!(max_velocity_age_s >= 0)) return bad("max_velocity_age_s", "must be >= 0");
  if (!(head_consistency_alpha > 0 && head_consistency_alpha < 1))
    return bad("head_consistency_alpha", "must be in (0, 1)");
  if (!gyro_health.isValid(&err)) {
    if (why) *why = err;  // already "'<key>': ..."
    return false;
  }
  return true;
}

const char* toString(FusionOptions::Update u) {
  return u == FusionOptions::Update::kStarVectors ? "stars" : "attitude";
}

std::string formatLoopTime(double t_s) {
  char b[64];
  std::snprintf(b, sizeof b, "t = %.6f s", t_s);
  return b;
}

const char* toString(FixUse u) {
  switch (u) {
    case FixUse::kNoFix: return "none";
    case FixUse::kInitialized: return "initialized";
    case FixUse::kReinitialized: return "reinitialized";
    case FixUse::kAccepted: return "accepted";
    case FixUse::kRejected: return "rejected";
    case FixUse::kIgnored: return "ignored";
    case FixUse::kUnfiltered: return "unfiltered";
    case FixUse::kClockRefused: return "clock_refused";
  }
  return "?";
}

bool FusionLoop::Event::operator<(const Event& o) const {
  if (t != o.t) return t > o.t;
  if (kind != o.kind) return kind > o.kind;
  return seq > o.seq;
}

static FusionOptions validated(FusionOptions o) {
  std::string why;
  if (!o.isValid(&why)) throw InputError("fusion option " + why);
  return o;
}

FusionLoop::FusionLoop(FusionOptions options, StarDirection star_direction)
    : opts_(validated(std::move(options))),
      star_direction_(std::move(star_direction)),
      filter_(opts_.filter),
      health_(opts_.gyro_health),
      head_threshold_(opts_.head_consistency_alpha, 3 * (kMaxHeads - 1)) {
  recent_.reserve(kRateRing);
  ahead_.reserve(kRateRing);
}

void FusionLoop::warn(const std::string& msg) {
  ++warning_count_;
  if (static_cast<int>(warnings_.size()) < opts_.max_warnings) warnings_.push_back(msg);
}

// ---- events ----------------------------------------------------------------------------

void FusionLoop::pushGyro(double t, const Vec3& rate_gyro) {
  if (gyroless()) {
    if (gyro_ignored_++ == 0)
      warn("gyro samples (first at " + formatLoopTime(t) +
           ") not used: the filter model is gyroless");
    return;
  }
  Event e{t, kGyro, 0, 0, opts_.R_body_gyro * rate_gyro, std::nullopt, {}};
  push(std::move(e));
}

void FusionLoop::pushVelocity(double t, const Vec3& velocity_km_s) {
  if (!opts_.velocity_aberration) {
    if (velocity_ignored_++ == 0)
      warn("velocity samples (first at " + formatLoopTime(t) +
           ") not used: velocity_aberration is off");
    return;
  }
  // Faster than light is not a velocity (and would make the aberration undefined).
  if (!velocity_km_s.allFinite() || !(velocity_km_s.norm() < 0.1 * kSpeedOfLightKmS)) {
    warn("velocity sample at " + formatLoopTime(t) + " not finite or above c/10: dropped");
    return;
  }
  push(Event{t, kVelocity, 0, 0, velocity_km_s, std::nullopt, {}});
}

void FusionLoop::pushFrame(double t, uint64_t tag, int head) {
  push(Event{t, kFrame, 0, tag, Vec3::Zero(), std::nullopt, {}, head});
}

void FusionLoop::pushFix(double t, uint64_t tag, FrameResult fix, int head) {
  push(Event{t, kFrame, 0, tag, Vec3::Zero(), std::move(fix), {}, head});
}

void FusionLoop::pushMarker(double t, uint64_t tag) {
  push(Event{t, kMarker, 0, tag, Vec3::Zero(), std::nullopt, {}});
}

void FusionLoop::push(Event e) {
  static const char* const kNames[] = {"gyro sample", "velocity sample", "frame", "marker"};
  const std::pair<double, int> key{e.t, e.kind};
  if (!std::isfinite(e.t)) {
    warn(std::string(kNames[e.kind]) + " with a non-finite time: dropped");
    return;
  }
  if (last_processed_ && key <= *last_processed_) {
    const bool dup = key == *last_processed_;
    if (dup && e.kind == kFrame) {
      warn("frame of head " + std::to_string(e.head) + " at " + formatLoopTime(e.t) +
           " arrived after the step of that time was taken (a duplicate, or later than the "
           "reorder window): dropped");
      return;
    }
    warn(std::string(dup ? "duplicate " : "out-of-order ") + kNames[e.kind] + " at " +
         formatLoopTime(e.t) +
         (dup ? "" : " (already processed up to " + formatLoopTime(last_processed_->first) + ")") +
         ": dropped");
    return;
  }
  if (e.kind == kGyro) {
    newest_gyro_t_ = std::max(newest_gyro_t_.value_or(e.t), e.t);
    ++gyro_since_frame_;
  } else if (e.kind == kFrame) {
    const bool ahead = clockAhead(e);
    gyro_since_frame_ = 0;
    if (ahead) {
      refuseFrame(e);
      return;
    }
  }
  for (const Event& q : queue_) {
    if (q.t == e.t && q.kind == e.kind && q.head == e.head) {
      warn(std::string("duplicate ") + kNames[e.kind] + " at " + formatLoopTime(e.t) + ": dropped");
      return;
    }
  }
  e.seq = seq_++;
  newest_t_ = std::max(newest_t_, e.t);
  queue_.push_back(std::move(e));
  std::push_heap(queue_.begin(), queue_.end());
  const double ready_before = newest_t_ - opts_.reorder_window_s;
  processWhile([ready_before](const Event& next) { return next.t <= ready_before; });
}

bool FusionLoop::clockAhead(Event& e) const {
  // Events arrive in time order (a rawlog is written as they come, a live fix after its
  // processing), so a frame can be ahead of the newest gyro sample by at most the ordering
  // slack and the gyro's own sample interval (and its jitter: gyro_gap_factor). Further ahead,
  // the camera stamped a time that has not come yet on the gyro's clock.
  // A gyro that sent nothing since the previous frame is silent (a gap), not behind: the
  // frame is coasted to as before. A live gyro keeps sending between frames.
  if (!opts_.check_camera_clock || !newest_gyro_t_ || gyro_dt_nominal_ <= 0 || gyro_lost_ ||
      gyro_since_frame_ == 0)
    return false;
  const double ahead = e.t - *newest_gyro_t_;
  const double slack = opts_.reorder_window_s + opts_.gyro_gap_factor * gyro_dt_nominal_;
  if (!(ahead > slack)) return false;
  char b[200];
  std::snprintf(b, sizeof b,
                "camera clock %.3f s ahead of the gyro's (frame stamped %s, newest gyro sample "
                "at %s): frame not processed",
                ahead, formatLoopTime(e.t).c_str(), formatLoopTime(*newest_gyro_t_).c_str());
  e.refused = b;
  return true;
}

void FusionLoop::refuseFrame(Event& e) {
  // Reported at once, in arrival order: queued at its stamp it would hold every later event
  // (and a genuine frame of the same stamp would be dropped as its duplicate).
  ++clock_refused_;
  warn(e.refused);
  FrameResult refused;
  if (e.fix) refused = std::move(*e.fix);  // a live fix keeps what it claimed
  if (!refused.hasAttitude()) {
    refused.mode = StarTrackerMode::kFailed;
    refused.failure = FrameFailure::kClockRefused;
  }
  refused.detail = e.refused;
  FusionStep s;
  s.t = e.t;
  s.tag = e.tag;
  s.is_frame = true;
  s.frame = &refused;
  s.use = FixUse::kClockRefused;  // no filter state at a stamp the gyro has not reached
  s.heads.push_back({e.tag, e.head, &refused});
  emit(s);
}

void FusionLoop::flush() {
  processWhile([](const Event&) { return true; });
}

void FusionLoop::processBefore(double t) {
  const std::pair<double, int> frame{t, kFrame};
  processWhile([&frame](const Event& next) { return std::make_pair(next.t, next.kind) < frame; });
}

template <class Predicate>
void FusionLoop::processWhile(Predicate ready) {
  // The queue is a heap in (time, kind, arrival) order: front() is the next event.
  while (!queue_.empty() && ready(queue_.front())) {
    std::pop_heap(queue_.begin(), queue_.end());
    Event next = std::move(queue_.back());
    queue_.pop_back();
    process(next);
  }
}

void FusionLoop::process(Event& e) {
  last_processed_ = {e.t, e.kind};
  switch (e.kind) {
    case kGyro: onGyro(e.t, e.rate); break;
    case kVelocity:
      // A few kept: a frame asks for the newest sample up to its own time, and samples up to
      // the reorder window later may already be processed.
      if (velocities_.size() == 8) velocities_.erase(velocities_.begin());
      velocities_.emplace_back(e.t, e.rate);
      break;
    case kFrame: {
      // Every head's frame of this time stamp is one step: they are next in the heap.
      group_.clear();
      group_.push_back(std::move(e));
      while (!queue_.empty() && queue_.front().kind == kFrame && queue_.front().t == group_[0].t) {
        std::pop_heap(queue_.begin(), queue_.end());
        group_.push_back(std::move(queue_.back()));
        queue_.pop_back();
      }
      onFrames(group_);
      break;
    }
    case kMarker: {
      FusionStep s;
      s.t = e.t;
      s.tag = e.tag;
      s.filter = stateAt(e.t);
      emit(s);
      break;
    }
    default: ST_ASSERT(false);
  }
}

// ---- gyro ------------------------------------------------------------------------------

void FusionLoop::onGyro(double t, const Vec3& rate_in) {
  Vec3 rate = rate_in;
  if (!rate.allFinite()) {
    warn("gyro sample at " + formatLoopTime(t) + " has a non-finite rate: dropped");
    return;
  }
  if (gyro_lost_) {
    gyro_lost_ = false;
    reinit_pending_ = true;
    warn("gyro samples again at " + formatLoopTime(t) +
         ": re-initialising the filter from lost-in-space");
    last_gyro_t_.reset();  // no gap to coast through: the attitude restarts from a fix
  }
  double dt = 0;
  if (last_gyro_t_) {
    dt = t - *last_gyro_t_;
    if (dt > 0 && (gyro_dt_nominal_ == 0 || dt < gyro_dt_nominal_)) gyro_dt_nominal_ = dt;
  }
  if (last_gyro_t_ && gyro_dt_nominal_ > 0 && dt > opts_.gyro_gap_factor * gyro_dt_nominal_) {
    char b[160];
    std::snprintf(b, sizeof b, "gyro gap of %.3f s ending at %s: coasted", dt, formatLoopTime(t).c_str());
    warn(b);
    // The sample is the mean rate over its own interval only: coast up to its start.
    coastTo(t - gyro_dt_nominal_);
  }
  checkHealth(t, dt, rate);
  in_gap_ = false;
  last_gyro_t_ = t;
  if (recent_.size() < kRateRing) {
    recent_.push_back({t, rate});
  } else {
    recent_[recent_next_ % kRateRing] = {t, rate};
  }
  ++recent_next_;
  if (filter_.initialized() && t > filter_.time()) filter_.propagate(rate, t);
}

void FusionLoop::checkHealth(double t, double dt, Vec3& rate) {
  // The checks need the sample interval: none on the first sample, and across a gap the
  // nominal one (a gap's sample is the mean over its own interval only).
  if (!(dt > 0) || gyro_dt_nominal_ <= 0) return;
  const double sigma_s = opts_.filter.arw_rad_rt_s / std::sqrt(gyro_dt_nominal_);
  const GyroSampleCheck c =
      health_.check(opts_.R_body_gyro.transpose() * rate, gyro_dt_nominal_, sigma_s);
  rate = opts_.R_body_gyro * c.rate;
  if (!c.step_error.isZero() && filter_.initialized()) {
    // Samples replaced as spikes were a real rate step: put their rotation back, and their
    // size into the covariance (the step's timing within them is not known).
    const Vec3 e = opts_.R_body_gyro * c.step_error;
    Mat6 P = filter_.covariance();
    P.topLeftCorner<3, 3>() += Mat3(e.cwiseAbs2().asDiagonal());
    filter_.initialize(filter_.time(), filter_.attitude() * quatExp(e), filter_.bias(), P);
  }
  if (!c.changed) return;
  if (!c.healthy) {
    gyro_unhealthy_ = true;
    filter_suspended_ = true;
    reinit_pending_ = false;
    warn("gyro unhealthy at " + formatLoopTime(t) + ": " + c.why +
         ": the filter is suspended; frames are solved lost-in-space and their fixes reported "
         "unfiltered until the gyro passes its checks again");
  } else {
    gyro_unhealthy_ = false;
    if (filter_.initialized()) {
      reinit_pending_ = true;
    } else {
      filter_suspended_ = false;
    }
    warn("gyro " + c.why + " at " + formatLoopTime(t) +
         ": re-initialising the filter from lost-in-space");
  }
}

Vec3 FusionLoop::meanRate(double t, const std::vector<TimedRate>& extra) const {
  // The samples of the last rate_window_s up to t (at least the newest one): one sample
  // carries the full white rate noise.
  Vec3 sum = Vec3::Zero();
  int n = 0;
  const TimedRate* newest = nullptr;
  auto take = [&](const TimedRate& r) {
    if (r.t > t) return;
    if (!newest || r.t > newest->t) newest = &r;
    if (r.t > t - opts_.rate_window_s) {
      sum += r.rate;
      ++n;
    }
  };
  for (const TimedRate& r : recent_) take(r);
  for (const TimedRate& r : extra) take(r);
  if (n > 0) return sum / n;
  return newest ? newest->rate : filter_.bias();
}

bool FusionLoop::gyroStale(double t) const {
  return last_gyro_t_ && gyro_dt_nominal_ > 0 &&
         t - *last_gyro_t_ > opts_.gyro_gap_factor * gyro_dt_nominal_;
}

bool FusionLoop::gyroLost(double t) const {
  return gyro_lost_ ||
         (filter_.initialized() && gyroStale(t) && t - *last_gyro_t_ > opts_.max_gyro_coast_s);
}

void FusionLoop::coastTo(double t) {
  if (!filter_.initialized() || !(t > filter_.time())) return;
  // Without gyro samples the rate is held at the mean of the last samples. That rate's error
  // is constant over the coast, not white: its variance sigma_v^2 / T_mean (T_mean = the
  // averaging time) grows the attitude variance by tau^2 sigma_v^2 / T_mean on top of the
  // filter's own process noise (which models the white rate noise of real samples).
  const double from = last_gyro_t_ ? *last_gyro_t_ : filter_.time();
  int n = 0;
  for (const TimedRate& r : recent_) n += r.t > from - opts_.rate_window_s;
  const double t_mean = std::max(1, n) * std::max(gyro_dt_nominal_, 1e-3);
  const double tau = t - filter_.time();
  const double sv = filter_.options().arw_rad_rt_s;
  Mat6 P = filter_.covariance();
  P.topLeftCorner<3, 3>() += Mat3::Identity() * (tau * tau * sv * sv / t_mean);
  const Vec3 rate = meanRate(from, {});
  filter_.initialize(filter_.time(), filter_.attitude(), filter_.bias(), P);
  filter_.propagate(rate, t);
}

// ---- frames ----------------------------------------------------------------------------

// GCC 12 reports a false "may be used uninitialized" inside Eigen's AVX code when the filter
// (fixed-size 6x6 matrices) is copied.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
std::optional<Vec3> FusionLoop::velocityAt(double t) const {
  std::optional<std::pair<double, Vec3>> v;
  for (auto it = velocities_.rbegin(); it != velocities_.rend() && !v; ++it)
    if (it->first <= t) v = *it;
  for (const Event& e : queue_) {
    if (e.kind == kVelocity && e.t <= t && (!v || e.t > v->first)) v = std::make_pair(e.t, e.rate);
  }
  if (!v) return std::nullopt;
  if (t - v->first > opts_.max_velocity_age_s) {
    if (!velocity_stale_warned_) {
      velocity_stale_warned_ = true;
      const_cast<FusionLoop*>(this)->warn(
          "velocity at " + formatLoopTime(t) + " is " + std::to_string(t - v->first) +
          " s old (max_velocity_age_s): frames not corrected for aberration until a new sample");
    }
    return std::nullopt;
  }
  velocity_stale_warned_ = false;
  return v->second;
}

FrameInputs FusionLoop::frameInputs(double t) const {
  FrameInputs in;
  in.observer_velocity_km_s = velocityAt(t);
  // Gyro samples still held for ordering are already known: a live tracker asks ahead of the
  // filter, and one noisy sample extrapolated over the whole window would be worse.
  std::vector<TimedRate>& ahead = ahead_;
  ahead.clear();
  for (const Event& e : queue_) {
    if (e.kind == kGyro && e.t <= t && e.rate.allFinite()) ahead.push_back({e.t, e.rate});
  }
  std::sort(ahead.begin(), ahead.end(), [](const auto& a, const auto& b) { return a.t < b.t; });
  const bool have_rate = !recent_.empty() || !ahead.empty();
  const bool stale = ahead.empty() && gyroStale(t);
  if (reinit_pending_ || !opts_.filter_enabled || gyro_unhealthy_ ||
      (ahead.empty() && gyroLost(t))) {
    in.force_lost_in_space = true;
  } else if (filter_.initialized()) {
    MekfPrediction p;
    if (ahead.empty()) {
      p = filter_.predictAt(t);
    } else {
      AttitudeMekf copy = filter_;
      for (const TimedRate& r : ahead) {
        if (r.t > copy.time()) copy.propagate(r.rate, r.t);
      }
      p = copy.predictAt(t);
    }
    AttitudePrediction a;
    a.q_ib = p.q_ib;
    a.cov_body = p.attitudeCov();
    a.rate_body = gyroless() ? p.rate : Vec3(meanRate(t, ahead) - p.bias);
    if (gyroless()) a.cov_rate_body = p.P.bottomRightCorner<3, 3>();
    in.prediction = a;
    return in;
  }
  // No attitude yet (or a re-initialisation pending): the gyro's rate still tells
  // lost-in-space how the stars streak (the unknown bias, a few deg/h, is nothing next to a
  // streak).
  if (have_rate && !stale) in.rate_body = meanRate(t, ahead) - filter_.bias();
  return in;
}
#pragma GCC diagnostic pop

void FusionLoop::onFrames(std::vector<Event>& group) {
  const double t = group.front().t;
  if (filter_.initialized() && !gyro_lost_ && gyroStale(t)) {
    if (gyroLost(t)) {
      char b[96];
      std::snprintf(b, sizeof b, "%.3f s (max_gyro_coast_s %.3f s)", t - *last_gyro_t_,
                    opts_.max_gyro_coast_s);
      warn("gyro lost: no gyro sample since " + formatLoopTime(*last_gyro_t_) +
           " at the frame at " + formatLoopTime(t) + ", " + b +
           ": the filter is suspended; frames are solved lost-in-space and their fixes "
           "reported unfiltered until the gyro returns");
      gyro_lost_ = filter_suspended_ = true;
    } else {
      if (!in_gap_) {
        warn("gyro gap: no gyro sample since " + formatLoopTime(*last_gyro_t_) +
             " at the frame at " + formatLoopTime(t) + ": coasting on the mean of the last rates");
        in_gap_ = true;
      }
      coastTo(t);
    }
  }
  // Every head gets the same inputs: the filter's state before any of them is used.
  std::optional<FrameInputs> inputs;
  made_.resize(group.size());
  FusionStep s;
  s.t = t;
  s.tag = group.front().tag;
  s.is_frame = true;
  for (std::size_t h = 0; h < group.size(); ++h) {
    Event& e = group[h];
    if (e.fix) {
      made_[h] = std::move(*e.fix);
    } else {
      ST_ASSERT(processor_);  // pushFrame without a processor is a caller bug
      if (!inputs) inputs = frameInputs(t);
      made_[h] = processor_(e.tag, t, *inputs);
    }
    s.heads.push_back({e.tag, e.head, &made_[h]});
  }
  FrameResult joint;
  if (s.heads.size() == 1) {
    s.frame = &made_[0];
    s.use = useFix(t, made_[0], s.update);
  } else {
    useHeads(t, s.heads, s, joint);
  }
  s.filter = stateAt(t);
  emit(s);
}

void FusionLoop::useHeads(double t, const std::vector<HeadFrame>& heads, FusionStep& s,
                          FrameResult& joint) {
  std::vector<HeadFix> fixes;
  const FrameResult* first = nullptr;
  for (const HeadFrame& h : heads) {
    if (!h.frame->hasAttitude()) continue;
    fixes.push_back({h.frame->q_ib, h.frame->cov_body});
    if (!first) first = h.frame;
  }
  s.frame = first ? first : heads.front().frame;
  if (fixes.size() < 2) {
    s.use = useFix(t, *s.frame, s.update);
    return;
  }
  const JointFix j = jointFix(fixes);
  s.heads_chi2 = j.chi2;
  s.heads_dof = j.dof;
  const bool agree = j.ok && j.dof <= head_threshold_.maxDof() && j.chi2 <= head_threshold_(j.dof);
  if (agree) {
    // One fix of all heads' stars, in the body frame (star-vector updates use every star).
    joint.mode = StarTrackerMode::kTracking;
    joint.prediction = first->prediction;
    for (const HeadFrame& h : heads) {
      const FrameResult& f = *h.frame;
      if (!f.hasAttitude()) continue;
      // Lost-in-space if any head is: only that re-initialises a filter (useFix).
      if (f.mode == StarTrackerMode::kLostInSpace) joint.mode = StarTrackerMode::kLostInSpace;
      for (MatchedStar m : f.stars) {
        m.v_cam = f.R_body_cam * m.v_cam;
        joint.stars.push_back(m);
      }
      joint.num_blobs += f.num_blobs;
      joint.timings.total += f.timings.total;
      joint.model_error_px = std::max(joint.model_error_px, f.model_error_px);
    }
    joint.q_ib = j.q_ib;
    joint.cov_body = j.cov_body;
    joint.rate = first->rate;
    joint.R_body_cam = Mat3::Identity();
    s.heads_merged = true;
    s.frame = &joint;
    s.use = useFix(t, joint, s.update);
    return;
  }
  char b[160];
  std::snprintf(b, sizeof b, "%zu heads' fixes disagree at %s (chi2 %.1f > %.1f, %d dof)",
                fixes.size(), formatLoopTime(t).c_str(), j.chi2,
                j.dof <= head_threshold_.maxDof() ? head_threshold_(j.dof) : 0.0, j.dof);
  const bool gated = opts_.filter_enabled && !gyro_lost_ && !gyro_unhealthy_ &&
                     filter_.initialized() && !reinit_pending_;
  if (!gated) {
    // Nothing to tell the right head from the wrong one: no fix rather than a wrong one.
    warn(std::string(b) + " and no filter to arbitrate: no fix this step");
    joint.mode = StarTrackerMode::kFailed;
    joint.failure = FrameFailure::kRejected;
    joint.detail = "heads disagree";
    s.frame = &joint;
    s.use = FixUse::kNoFix;
    return;
  }
  warn(std::string(b) + ": each goes through the filter's gate on its own");
  // The step reports the first head whose fix the filter took (else the first one's use).
  s.use = FixUse::kNoFix;
  for (const HeadFrame& h : heads) {
    if (!h.frame->hasAttitude()) continue;
    MekfUpdateResult u;
    const FixUse use = useFix(t, *h.frame, u);
    if (s.use == FixUse::kNoFix || (use == FixUse::kAccepted && s.use != FixUse::kAccepted)) {
      s.use = use;
      s.update = u;
      s.frame = h.frame;
    }
  }
}

FixUse FusionLoop::useFix(double t, const FrameResult& fix, MekfUpdateResult& u) {
  if (!fix.hasAttitude()) return FixUse::kNoFix;
  if (!opts_.filter_enabled || gyro_lost_ || gyro_unhealthy_) return FixUse::kUnfiltered;
  const bool lis = fix.mode == StarTrackerMode::kLostInSpace;
  if (!filter_.initialized()) {
    initializeFrom(t, fix);
    return FixUse::kInitialized;
  }
  if (reinit_pending_) {
    if (!lis) return FixUse::kIgnored;
    if (gyroless()) {
      initializeFrom(t, fix);
      reinit_pending_ = filter_suspended_ = false;
      ++reinits_;
      return FixUse::kReinitialized;
    }
    // Keep what the filter learned about the bias; the attitude restarts from the fix.
    filter_.resetAttitude(t, fix.q_ib, fix.cov_body);
    reinit_pending_ = filter_suspended_ = false;
    ++reinits_;
    return FixUse::kReinitialized;
  }
  if (t > filter_.time()) filter_.predictTo(t);
  u = update(t, fix);
  if (u.accepted) return FixUse::kAccepted;
  if (filter_.consecutiveRejections() >= opts_.reinit_after_rejections) {
    warn(std::to_string(filter_.consecutiveRejections()) +
         " star-tracker fixes in a row rejected by the filter at " + formatLoopTime(t) +
         ": re-initialising from lost-in-space");
    reinit_pending_ = true;
  }
  return FixUse::kRejected;
}

void FusionLoop::initializeFrom(double t, const FrameResult& fix) {
  if (!gyroless() || !fix.rate) {
    filter_.initialize(t, fix.q_ib, fix.cov_body);
    return;
  }
  // The fix's own frame-to-frame rate starts the rate state (its covariance the prior): the
  // first fix of a run has none (zero rate, the options' prior sigma).
  Mat6 P = Mat6::Zero();
  P.topLeftCorner<3, 3>() = fix.cov_body;
  P.bottomRightCorner<3, 3>() = fix.rate->cov_body;
  filter_.initialize(t, fix.q_ib, fix.rate->rate_body, P);
}

MekfUpdateResult FusionLoop::update(double t, const FrameResult& fix) {
  if (opts_.update == FusionOptions::Update::kAttitude || fix.stars.size() < 2 ||
      !star_direction_) {
    return filter_.updateAttitude(fix.q_ib, fix.cov_body);
  }
  // Tight coupling: per-star sigma from the fix covariance. For n stars of equal sigma the
  // QUEST information matrix is sum (I - b b^T) / sigma^2, whose trace is 2 n / sigma^2
  // (seed 004 §6 covariance of the attitude solution).
  const Mat3 info = fix.cov_body.inverse();
  const double n = static_cast<double>(fix.stars.size());
  const double sigma = std::sqrt(2.0 * n / std::max(info.trace(), 1e-300));
  std::vector<StarVectorMeasurement> meas;
  meas.reserve(fix.stars.size());
  const std::optional<Vec3> v = velocityAt(t);  // the fix's tracker had the same
  for (const MatchedStar& m : fix.stars) {
    const std::optional<Vec3> r = star_direction_(m.catalog_id);
    if (!r) continue;
    meas.push_back(StarVectorMeasurement::fromSigma((fix.R_body_cam * m.v_cam).normalized(),
                                                    v ? applyAberration(*r, *v) : *r, sigma));
  }
  if (meas.empty()) return filter_.updateAttitude(fix.q_ib, fix.cov_body);
  return filter_.updateStarVectors(meas);
}

FilterState FusionLoop::stateAt(double t) const {
  FilterState s;
  s.initialized = filter_.initialized() && !filter_suspended_;
  if (!s.initialized) return s;
  if (t == filter_.time()) {
    s.q_ib = filter_.attitude();
    s.bias = filter_.bias();
    s.P = filter_.covariance();
    s.rate = filter_.rate();
  } else {
    const MekfPrediction p = filter_.predictAt(t);
    s.q_ib = p.q_ib;
    s.bias = p.bias;
    s.P = p.P;
    s.rate = p.rate;
  }
  s.gyroless = gyroless();
  if (s.gyroless) s.bias.setZero();
  s.q_ib = canonical(s.q_ib);
  return s;
}

void FusionLoop::emit(FusionStep& s) {
  if (callback_) callback_(s);
}

}  // namespace st

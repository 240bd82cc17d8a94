#include "app/live/live_navigator.hpp"

#include <mrpt/obs/CObservationIMU.h>

#include <algorithm>
#include <chrono>

namespace st::app {

LiveNavigator::LiveNavigator(const StarDatabase& db, const CameraModel& camera,
                             NavigatorOptions options, const std::string& csv_path)
    : nav_(db, camera, std::move(options), Navigator::Source::kStarTrackerFixes),
      report_(csv_path) {
  const NavigatorOptions& o = nav_.options();
  heads_.push_back({o.star_tracker_label, {}, {}});
  for (const std::string& head : o.head_labels)
    heads_.push_back({headFixLabel(o.star_tracker_label, head), {}, {}});
  // Each step is summarised and written as it finishes, then dropped: the navigator keeps
  // none (a one-hour run kept ~1 KB per frame of them, the memory growth of the soak).
  nav_.setKeepSteps(false);
  nav_.setStepCallback([this](const NavStep& s, const std::vector<CObservationStarTracker::Ptr>&) {
    report_.push(s);
    if (!s.has_frame || !s.fix) return;
    ++stats_.fixes;
    stats_.accepted += s.use == FixUse::kAccepted;
    stats_.rejected += s.use == FixUse::kRejected;
    stats_.ignored += s.use == FixUse::kIgnored;
  });
}

void LiveNavigator::push(const std::vector<mrpt::obs::CObservation::Ptr>& batch) {
  {
    std::lock_guard<std::mutex> lock(m_);
    const NavigatorOptions& o = nav_.options();
    for (const auto& obs : batch) {
      if (started_) {
        nav_.push(obs);
      } else {
        before_start_.push_back(obs);
      }
      const auto newer = [&](std::optional<mrpt::Clock::time_point>& newest) {
        if (!newest || obs->timestamp > *newest) newest = obs->timestamp;
      };
      if (obs->sensorLabel == o.gyro_label && dynamic_cast<mrpt::obs::CObservationIMU*>(obs.get())) {
        newer(newest_gyro_);
        gyro_stalled_ = false;
      } else if (const int h = headOfFix(obs->sensorLabel);
                 h >= 0 && dynamic_cast<CObservationStarTracker*>(obs.get())) {
        newer(heads_[static_cast<std::size_t>(h)].newest_fix);
      }
    }
  }
  arrived_.notify_all();
}

void LiveNavigator::start(std::optional<mrpt::Clock::time_point> first_frame) {
  started_ = true;
  auto held = std::move(before_start_);
  std::stable_sort(held.begin(), held.end(),
                   [](const auto& a, const auto& b) { return a->timestamp < b->timestamp; });
  // Replay's origin: the earliest observation it reads under one of the navigator's labels.
  const NavigatorOptions& o = nav_.options();
  std::optional<mrpt::Clock::time_point> origin = first_frame;
  for (const auto& obs : held) {
    const std::string& l = obs->sensorLabel;
    bool known = l == o.gyro_label || l == o.truth_label || l == o.camera_label ||
                 l == o.star_tracker_label || (!o.velocity_label.empty() && l == o.velocity_label);
    for (const std::string& head : o.head_labels)
      known = known || l == head || l == headFixLabel(o.star_tracker_label, head);
    if (known && (!origin || obs->timestamp < *origin)) origin = obs->timestamp;
  }
  if (origin) nav_.setTimeOrigin(*origin);
  for (const auto& obs : held) nav_.push(obs);
}

void LiveNavigator::flush() {
  std::lock_guard<std::mutex> lock(m_);
  if (!started_) start(std::nullopt);
  nav_.flush();
  report_.flush();
}

bool LiveNavigator::earlierEventsIn(mrpt::Clock::time_point t) const {
  // The gyro delivers in time order: one sample at or after t means all up to t are in. No
  // gyro seen (none configured, or not started) or one that stalled: nothing to wait for.
  const bool gyro_in = !newest_gyro_ || gyro_stalled_ || *newest_gyro_ >= t;
  // Each head's tracker makes one fix per frame it asks for, in order: its fix of the last
  // frame it asked for before t must be in (a head's frame of t itself is not earlier).
  for (const HeadSchedule& h : heads_) {
    const bool fix_in = !h.last_asked || *h.last_asked >= t ||
                        (h.newest_fix && *h.newest_fix >= *h.last_asked);
    if (!fix_in) return false;
  }
  return gyro_in;
}

int LiveNavigator::headOfFix(const std::string& label) const {
  for (std::size_t h = 0; h < heads_.size(); ++h)
    if (heads_[h].fix_label == label) return static_cast<int>(h);
  return -1;
}

FrameInputs LiveNavigator::frameInputs(mrpt::Clock::time_point t, int head) {
  std::unique_lock<std::mutex> lock(m_);
  // The latency a fix may have in the loop anyway: waiting longer would only delay a frame
  // whose fix could no longer be used.
  const auto wait = std::chrono::duration<double>(nav_.options().fusion.reorder_window_s);
  arrived_.wait_for(lock, wait, [&] { return stopping_ || earlierEventsIn(t); });
  if (!earlierEventsIn(t)) {
    ++stats_.off_schedule;
    if (!newest_gyro_ || *newest_gyro_ < t) gyro_stalled_ = true;
  }
  if (head >= 0 && head < static_cast<int>(heads_.size()))
    heads_[static_cast<std::size_t>(head)].last_asked = t;
  if (!started_) start(t);
  nav_.processBefore(t);
  return nav_.frameInputs(t);
}

void LiveNavigator::stopWaiting() {
  {
    std::lock_guard<std::mutex> lock(m_);
    stopping_ = true;
  }
  arrived_.notify_all();
}

bool LiveNavigator::current(Quat& q_ib, Mat3& P_att) const {
  std::lock_guard<std::mutex> lock(m_);
  if (!nav_.filter().initialized()) return false;
  q_ib = nav_.filter().attitude();
  P_att = nav_.filter().attitudeCov();
  return true;
}

LiveNavigator::Stats LiveNavigator::stats() const {
  std::lock_guard<std::mutex> lock(m_);
  Stats s = stats_;
  s.reinits = nav_.reinitializations();
  s.warnings = nav_.warningCount();
  return s;
}

void LiveNavigator::printSummaries(std::FILE* out) const {
  std::lock_guard<std::mutex> lock(m_);
  report_.print(out);
}

int LiveNavigator::finishCsv() {
  std::lock_guard<std::mutex> lock(m_);
  return report_.finishCsv();
}

std::vector<std::string> LiveNavigator::warnings() const {
  std::lock_guard<std::mutex> lock(m_);
  return nav_.warnings();
}

}  // namespace st::app

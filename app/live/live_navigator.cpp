#include "app/live/live_navigator.hpp"

namespace st::app {

LiveNavigator::LiveNavigator(const StarDatabase& db, const CameraModel& camera,
                             NavigatorOptions options)
    : nav_(db, camera, std::move(options), Navigator::Source::kStarTrackerFixes) {
  nav_.setStepCallback([this](const NavStep& s, const CObservationStarTracker::Ptr&) {
    if (!s.has_frame || !s.fix) return;
    ++stats_.fixes;
    stats_.accepted += s.use == FixUse::kAccepted;
    stats_.rejected += s.use == FixUse::kRejected;
    stats_.ignored += s.use == FixUse::kIgnored;
  });
}

void LiveNavigator::push(const mrpt::obs::CObservation::Ptr& obs) {
  std::lock_guard<std::mutex> lock(m_);
  nav_.push(obs);
}

void LiveNavigator::flush() {
  std::lock_guard<std::mutex> lock(m_);
  nav_.flush();
}

FrameInputs LiveNavigator::frameInputs(mrpt::Clock::time_point t) const {
  std::lock_guard<std::mutex> lock(m_);
  return nav_.frameInputs(t);
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

std::vector<NavStep> LiveNavigator::steps() const {
  std::lock_guard<std::mutex> lock(m_);
  return nav_.steps();
}

std::vector<std::string> LiveNavigator::warnings() const {
  std::lock_guard<std::mutex> lock(m_);
  return nav_.warnings();
}

}  // namespace st::app

#include "app/live/step_report.hpp"

#include "sensors/tracking/star_tracker.hpp"

namespace st::app {

StepReport::StepReport(const std::string& csv_path, bool keep) : keep_(keep) {
  if (!csv_path.empty()) csv_ = std::make_unique<NavStepCsvWriter>(csv_path);
}

void StepReport::push(const NavStep& s) {
  if (s.has_frame) {
    ++counts_.frames;
    counts_.frame_time_s += s.frame_time_s;
    counts_.solved += s.fix;
    counts_.lost_in_space += s.mode == StarTrackerMode::kLostInSpace;
    counts_.reacquired += reacquiredInFrame(s.mode, s.reason);
    counts_.tracking += s.mode == StarTrackerMode::kTracking;
    counts_.rejected += s.use == FixUse::kRejected;
  }
  truth_rates_.push(s, [this](const NavStep& f) { final(f); });
}

void StepReport::flush() {
  truth_rates_.flush([this](const NavStep& f) { final(f); });
}

void StepReport::final(const NavStep& s) {
  summary_.add(s);
  integrity_.add(s);
  if (csv_) csv_->write(s);
  if (keep_) kept_.push_back(s);
}

void StepReport::print(std::FILE* out) const {
  summary_.print(out);
  summary_.printRates(out);
  printIntegritySummary(integrity_.stats(), out);
}

int StepReport::finishCsv() { return csv_ ? csv_->finish() : -1; }

}  // namespace st::app

#include "app/live/sensor_runner.hpp"

#include "sensors/mrpt/image_source.hpp"
#include "sensors/mrpt/star_tracker_sensor.hpp"

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/core/exceptions.h>
#include <mrpt/obs/CObservation.h>

#include <chrono>
#include <sstream>

#include "common/errors.hpp"

namespace st::app {

namespace {

// MRPT wraps exceptions thrown inside loadConfig() into a stacked exception whose text holds
// call-stack lines: keep the line of the original message (the one naming the section or
// key, else the first line that is not stack decoration).
std::string usefulMessage(const std::exception& e, const std::string& section) {
  // Ours names the file, section, key and value already (e.g. a scenario's bad key).
  if (dynamic_cast<const InputError*>(&e)) return e.what();
  const std::string all = mrpt::exception_to_str(e);
  std::istringstream in(all);
  std::string line, message, first;
  while (std::getline(in, line)) {
    const auto m = line.find("Message:");
    if (m != std::string::npos) line = line.substr(line.find_first_not_of(' ', m + 8));
    if (line.find("'" + section + "'") != std::string::npos) return line;
    if (m != std::string::npos && message.empty()) message = line;
    if (first.empty() && !line.empty() && line.find("====") == std::string::npos) first = line;
  }
  if (!message.empty()) return message;
  return first.empty() ? all : first;
}

}  // namespace

// ---- queue ----------------------------------------------------------------------------

void ObservationQueue::push(std::vector<mrpt::obs::CObservation::Ptr> obs) {
  {
    std::lock_guard<std::mutex> lock(m_);
    for (auto& o : obs) q_.push_back(std::move(o));
  }
  cv_.notify_one();
}

std::vector<mrpt::obs::CObservation::Ptr> ObservationQueue::takeAll(double timeout_s) {
  std::unique_lock<std::mutex> lock(m_);
  cv_.wait_for(lock, std::chrono::duration<double>(timeout_s), [&] { return !q_.empty(); });
  std::vector<mrpt::obs::CObservation::Ptr> out;
  out.swap(q_);
  return out;
}

void ObservationQueue::report(const std::string& message) {
  {
    std::lock_guard<std::mutex> lock(m_);
    reports_.push_back(message);
  }
  cv_.notify_one();
}

std::vector<std::string> ObservationQueue::takeReports() {
  std::lock_guard<std::mutex> lock(m_);
  std::vector<std::string> out;
  out.swap(reports_);
  return out;
}

// ---- configuration --------------------------------------------------------------------

std::vector<SensorSpec> createSensors(const mrpt::config::CConfigFileBase& cfg,
                                      const std::string& source) {
  std::vector<std::string> sections;
  cfg.getAllSections(sections);
  std::vector<SensorSpec> out;
  for (const auto& s : sections) {
    if (!cfg.keyExists(s, "driver")) continue;
    SensorSpec spec;
    spec.section = s;
    spec.driver = cfg.read_string(s, "driver", "");
    spec.sensor.reset(mrpt::hwdrivers::CGenericSensor::createSensor(spec.driver));
    if (!spec.sensor) {
      throw InputError(source + ": section '" + s + "' key 'driver': unknown sensor class '" + spec.driver +
                       "' (not registered with MRPT's sensor factory)");
    }
    if (!cfg.keyExists(s, "process_rate")) {
      throw InputError(source + ": section '" + s + "' key 'process_rate': missing");
    }
    try {
      spec.sensor->loadConfig(cfg, s);
    } catch (const std::exception& e) {
      // A message that names the section already is not prefixed with it a second time.
      const std::string why = usefulMessage(e, s);
      const std::string named = "section '" + s + "'";
      throw InputError(source + ": " +
                       (why.rfind(named, 0) == 0 ? "(" + spec.driver + ") " + why
                                                 : named + " (" + spec.driver + "): " + why));
    }
    if (!(spec.sensor->getProcessRate() > 0)) {
      throw InputError(source + ": section '" + s + "' key 'process_rate': must be > 0");
    }
    out.push_back(std::move(spec));
  }
  if (out.empty()) {
    throw InputError(source + ": no sensor sections (a section with 'driver = <class>')");
  }
  return out;
}

// ---- runner ---------------------------------------------------------------------------

SensorRunner::SensorRunner(SensorSpec spec, ObservationQueue& queue)
    : spec_(std::move(spec)), queue_(queue) {}

SensorRunner::~SensorRunner() { stop(); }

void SensorRunner::start() { thread_ = std::thread([this] { run(); }); }

void SensorRunner::waitInitialized() {
  std::unique_lock<std::mutex> lock(m_);
  cv_.wait(lock, [&] { return initialized_.load(); });
}

void SensorRunner::go() {
  {
    std::lock_guard<std::mutex> lock(m_);
    go_ = true;
  }
  cv_.notify_all();
}

void SensorRunner::requestStop() {
  {
    std::lock_guard<std::mutex> lock(m_);
    stop_ = true;
  }
  cv_.notify_all();
}

void SensorRunner::stop() {
  requestStop();
  if (thread_.joinable()) thread_.join();
  if (state_ == State::kRunning || state_ == State::kStarting) state_ = State::kStopped;
}

void SensorRunner::run() {
  loop();
  exited_ = true;
}

void SensorRunner::loop() {
  const std::string who = "sensor '" + spec_.section + "' (" + spec_.driver + ")";
  try {
    spec_.sensor->initialize();
  } catch (const std::exception& e) {
    state_ = State::kFailed;
    bad_input_ = dynamic_cast<const InputError*>(&e) != nullptr;
    queue_.report(who + " failed to start: " + usefulMessage(e, spec_.section));
  }
  {
    std::unique_lock<std::mutex> lock(m_);
    initialized_ = true;
    cv_.notify_all();
    if (state_ == State::kFailed) return;
    cv_.wait(lock, [&] { return go_.load() || stop_.load(); });
  }
  if (stop_) return;
  state_ = State::kRunning;
  using clock = std::chrono::steady_clock;
  const auto period = std::chrono::duration_cast<clock::duration>(
      std::chrono::duration<double>(1.0 / spec_.sensor->getProcessRate()));
  auto next = clock::now();
  while (!stop_) {
    try {
      spec_.sensor->doProcess();
      mrpt::hwdrivers::CGenericSensor::TListObservations got;
      spec_.sensor->getObservations(got);
      std::vector<mrpt::obs::CObservation::Ptr> obs;
      for (auto& [t, o] : got) {
        if (auto p = std::dynamic_pointer_cast<mrpt::obs::CObservation>(o)) obs.push_back(p);
      }
      if (!obs.empty()) {
        count_ += obs.size();
        queue_.push(std::move(obs));
      }
      if (const auto* f = dynamic_cast<const FiniteSensor*>(spec_.sensor.get());
          f && f->finished()) {
        state_ = State::kFinished;
        // A star tracker's folder or scenario has ended, a simulated gyro's scenario too.
        queue_.report(who + " finished: it has no more data");
        return;
      }
    } catch (const std::exception& e) {
      state_ = State::kFailed;
      queue_.report(who + " stopped with an error: " + usefulMessage(e, spec_.section));
      return;
    }
    next += period;
    const auto now = clock::now();
    if (next < now) next = now;  // fallen behind: do not try to catch up in a burst
    std::unique_lock<std::mutex> lock(m_);
    cv_.wait_until(lock, next, [&] { return stop_.load(); });
  }
}

}  // namespace st::app

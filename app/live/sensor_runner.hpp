/// @file sensor_runner.hpp
/// The sensors of `startracker live`, rawlog-grabber style: every section of the .ini with a
/// `driver` key is one mrpt::hwdrivers::CGenericSensor (any class registered with MRPT's
/// factory: ours after registerStarTrackerClasses(), MRPT's own such as CCameraSensor), run in
/// its own thread: initialize(), then doProcess() at its process_rate; its observations go to
/// one shared queue. A sensor that throws is reported by its section name and stops; the
/// others keep running.
#pragma once
#include <mrpt/hwdrivers/CGenericSensor.h>
#include <mrpt/obs/CObservation.h>

#include <atomic>
#include <condition_variable>
#include <deque>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace mrpt::config {
class CConfigFileBase;
}

namespace st::app {

/// Observations from all sensor threads, in arrival order.
class ObservationQueue {
 public:
  void push(std::vector<mrpt::obs::CObservation::Ptr> obs);
  /// Waits up to `timeout_s` for something, then takes everything queued.
  std::vector<mrpt::obs::CObservation::Ptr> takeAll(double timeout_s);
  /// Messages from sensor threads (failures), taken by the main loop.
  void report(const std::string& message);
  std::vector<std::string> takeReports();

 private:
  std::mutex m_;
  std::condition_variable cv_;
  std::vector<mrpt::obs::CObservation::Ptr> q_;
  std::vector<std::string> reports_;
};

/// Reads the sensor sections of `cfg` and creates and configures each sensor (loadConfig).
/// Throws InputError naming the section (and the key when MRPT or the sensor names one) for
/// an unknown driver class, a missing process_rate, or a configuration the sensor rejects.
/// `source` names the file in messages.
struct SensorSpec {
  std::string section, driver;
  std::shared_ptr<mrpt::hwdrivers::CGenericSensor> sensor;
};
std::vector<SensorSpec> createSensors(const mrpt::config::CConfigFileBase& cfg,
                                      const std::string& source);

class SensorRunner {
 public:
  /// kFinished: the sensor or its source has no more data (a star tracker's folder of
  /// frames or simulated scenario ended, a FiniteSensor such as the simulated gyro at its
  /// scenario's end); not a failure.
  enum class State { kStarting, kRunning, kFailed, kStopped, kFinished };

  SensorRunner(SensorSpec spec, ObservationQueue& queue);
  ~SensorRunner();  // stops and joins

  /// Starts the thread: initialize(), then waits for go() before the doProcess() loop so
  /// that all sensors start their clocks together.
  void start();
  /// Blocks until initialize() has returned or thrown.
  void waitInitialized();
  void go();
  /// Asks the thread to end after its current doProcess() (returns at once).
  void requestStop();
  /// True once the thread has left its loop (or was never started).
  bool exited() const { return exited_ || !thread_.joinable(); }
  void stop();  // asks the thread to end and joins it

  State state() const { return state_; }
  /// initialize() refused its configuration (an InputError: a bad key, a missing file).
  bool failedOnInput() const { return bad_input_; }
  const std::string& section() const { return spec_.section; }
  const std::string& driver() const { return spec_.driver; }
  mrpt::hwdrivers::CGenericSensor& sensor() { return *spec_.sensor; }
  std::size_t observations() const { return count_; }

 private:
  void run();
  void loop();

  SensorSpec spec_;
  ObservationQueue& queue_;
  std::thread thread_;
  std::atomic<State> state_{State::kStarting};
  std::atomic<bool> stop_{false}, go_{false}, initialized_{false}, exited_{false};
  std::atomic<bool> bad_input_{false};
  std::atomic<std::size_t> count_{0};
  std::mutex m_;
  std::condition_variable cv_;
};

}  // namespace st::app

#include "sensors/sim/simulated_sensors.hpp"

#include <mrpt/config/CConfigFile.h>
#include <mrpt/system/filesystem.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <mutex>

#include "common/errors.hpp"
#include "sensors/sim/scenario.hpp"
#include "sensors/sim/sim_observations.hpp"

IMPLEMENTS_GENERIC_SENSOR(CSimulatedStarCamera, st)
IMPLEMENTS_GENERIC_SENSOR(CSimulatedGyro, st)

namespace st {

namespace {
std::mutex g_clock_mutex;
std::optional<mrpt::Clock::time_point> g_start;

std::string requireScenarioFile(const mrpt::config::CConfigFileBase& cfg,
                                const std::string& section) {
  const std::string f = cfg.read_string(section, "scenario_file", "");
  if (f.empty()) throw InputError("[" + section + "]: missing key 'scenario_file'");
  // A relative path that is not found from the working directory is taken relative to the
  // folder of the .ini file holding the section (rawlog-grabber runs from anywhere).
  namespace fs = std::filesystem;
  if (fs::path(f).is_relative() && !fs::exists(f))
    if (const auto* file = dynamic_cast<const mrpt::config::CConfigFile*>(&cfg)) {
      const fs::path alt = fs::path(file->getAssociatedFile()).parent_path() / f;
      if (fs::exists(alt)) return alt.string();
    }
  return f;
}

std::optional<uint64_t> optionalSeed(const mrpt::config::CConfigFileBase& cfg,
                                     const std::string& section) {
  if (!cfg.keyExists(section, "seed")) return std::nullopt;
  return cfg.read_uint64_t(section, "seed", 0);
}
}  // namespace

mrpt::Clock::time_point simulatedSensorsStart() {
  std::lock_guard<std::mutex> lock(g_clock_mutex);
  if (!g_start) g_start = mrpt::Clock::now();
  return *g_start;
}

double simulatedSensorsElapsed() {
  const auto start = simulatedSensorsStart();
  return std::chrono::duration<double>(mrpt::Clock::now() - start).count();
}

void resetSimulatedSensorsClock() {
  std::lock_guard<std::mutex> lock(g_clock_mutex);
  g_start.reset();
}

void registerSimulatedSensors() {
  CSimulatedStarCamera::doRegister();
  CSimulatedGyro::doRegister();
}

// ---- camera ---------------------------------------------------------------------------

CSimulatedStarCamera::CSimulatedStarCamera() { m_sensorLabel = kCameraLabel; }
CSimulatedStarCamera::~CSimulatedStarCamera() = default;

void CSimulatedStarCamera::loadConfig_sensorSpecific(const mrpt::config::CConfigFileBase& cfg,
                                                     const std::string& section) {
  scenario_file_ = requireScenarioFile(cfg, section);
  seed_ = optionalSeed(cfg, section);
  truth_label_ = cfg.read_string(section, "truth_label", truth_label_);
}

void CSimulatedStarCamera::setPathForExternalImages(const std::string& directory) {
  if (!mrpt::system::createDirectory(directory))
    throw InputError(directory + ": cannot create the external images folder");
  m_path_for_external_images = directory;
}

void CSimulatedStarCamera::initialize() {
  m_state = ssInitializing;
  scenario_ = std::make_unique<Scenario>(Scenario::load(scenario_file_));
  sim_ = std::make_unique<SkySimulator>(*scenario_, seed_.value_or(scenario_->seed));
  next_frame_ = 0;
  m_state = ssWorking;
}

bool CSimulatedStarCamera::finished() const {
  return scenario_ && next_frame_ >= scenario_->frameCount();
}

void CSimulatedStarCamera::doProcess() {
  if (!sim_ || finished()) return;
  const Scenario& sc = *scenario_;
  const double now = simulatedSensorsElapsed();
  // The newest frame whose exposure is over: t_k + T/2 <= now.
  const double ready = now - 0.5 * sc.sensor.exposure_s;
  if (ready < 0) return;
  const int last = std::min(sc.frameCount() - 1, static_cast<int>(std::floor(ready * sc.frame_rate_hz)));
  if (last < next_frame_) return;
  skipped_ += last - next_frame_;  // fallen behind: deliver only the newest frame
  const SimFrame f = sim_->frame(last);
  next_frame_ = last + 1;
  const auto stamp = simulatedSensorsStart() +
                     std::chrono::duration_cast<mrpt::Clock::duration>(std::chrono::duration<double>(f.t));
  std::vector<mrpt::serialization::CSerializable::Ptr> out;
  if (!f.dropped) {
    auto obs = makeCameraObservation(f.image, sc.camera, stamp, m_sensorLabel);
    if (!m_path_for_external_images.empty()) {
      char name[96];
      std::snprintf(name, sizeof(name), "%s_%06d.%s", m_sensorLabel.c_str(), f.index,
                    m_external_images_format.c_str());
      obs->image.saveToFile(m_path_for_external_images + "/" + name);
      obs->image.setExternalStorage(name);
    }
    out.push_back(obs);
    ++emitted_;
  }
  if (!truth_label_.empty()) out.push_back(makeTruthObservation(f.q_ib, f.truth, stamp, truth_label_));
  if (!out.empty()) appendObservations(out);
}

// ---- gyro -----------------------------------------------------------------------------

CSimulatedGyro::CSimulatedGyro() { m_sensorLabel = kGyroLabel; }
CSimulatedGyro::~CSimulatedGyro() = default;

void CSimulatedGyro::loadConfig_sensorSpecific(const mrpt::config::CConfigFileBase& cfg,
                                               const std::string& section) {
  scenario_file_ = requireScenarioFile(cfg, section);
  seed_ = optionalSeed(cfg, section);
}

void CSimulatedGyro::initialize() {
  m_state = ssInitializing;
  scenario_ = std::make_unique<Scenario>(Scenario::load(scenario_file_));
  if (!scenario_->gyro)
    throw InputError(scenario_file_ + ": the scenario has no [gyro] section for CSimulatedGyro");
  stream_ = std::make_unique<GyroStream>(*scenario_, seed_.value_or(scenario_->seed));
  done_ = false;
  m_state = ssWorking;
}

void CSimulatedGyro::doProcess() {
  if (!stream_ || done_) return;
  const double now = simulatedSensorsElapsed();
  const auto start = simulatedSensorsStart();
  GyroSample g;
  while (stream_->nextTime() <= now) {
    if (!stream_->next(g)) {
      done_ = true;
      break;
    }
    const auto stamp = start + std::chrono::duration_cast<mrpt::Clock::duration>(
                                   std::chrono::duration<double>(g.t));
    appendObservation(makeGyroObservation(g.rate, stamp, m_sensorLabel));
    ++emitted_;
  }
  if (stream_->nextTime() > scenario_->duration_s + 1e-9) done_ = true;
}

}  // namespace st

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

constexpr const char* kCameraDriver = kSimulatedCameraClass;
constexpr const char* kGyroDriver = "CSimulatedGyro";

SimulatedSensorKeys defaultKeys(bool camera) {
  SimulatedSensorKeys k;
  k.driver = camera ? kCameraDriver : kGyroDriver;
  k.sensorLabel = camera ? kCameraLabel : kGyroLabel;
  if (!camera) k.truth_label.clear();  // the gyro emits the truth only when asked
  return k;
}

/// Strict read when the section is ours: its driver names `self` or is absent (a sensor
/// built in code). Another driver owns the section's keys and checks them itself.
SimulatedSensorKeys readKeys(const IniReader& r, const std::string& section, bool camera) {
  SimulatedSensorKeys k = defaultKeys(camera);
  const std::string driver = r.str(section, "driver", k.driver);
  if (driver == k.driver) {
    simulatedSensorSchema(camera).read(r, section, k);
  } else {
    k.scenario_file = r.str(section, "scenario_file", "");
    k.seed = r.str(section, "seed", "");
    // Written empty means "no truth", as in the schema's own read (an absent key keeps the
    // default).
    if (r.exists(section, "truth_label")) k.truth_label = r.str(section, "truth_label", "");
    if (camera) k.scenario_head = r.integer(section, "scenario_head", 0);
  }
  if (k.scenario_file.empty()) throw InputError(r.whereKey(section, "scenario_file") + ": missing key");
  if (!k.seed.empty()) r.uint64(section, "seed", 0);  // a bad seed fails here, naming the key
  return k;
}

std::string resolveScenarioFile(const mrpt::config::CConfigFileBase& cfg, const std::string& f) {
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

std::optional<uint64_t> optionalSeed(const IniReader& r, const std::string& section,
                                     const SimulatedSensorKeys& k) {
  if (k.seed.empty()) return std::nullopt;
  return r.uint64(section, "seed", 0);
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

const SectionSchema<SimulatedSensorKeys>& simulatedSensorSchema(bool camera) {
  using K = SimulatedSensorKeys;
  auto make = [](bool cam) {
    auto s = SectionSchema<K>()
                 .choice("driver", &K::driver, {cam ? kCameraDriver : kGyroDriver}, "sensor class")
                 .add("process_rate", &K::process_rate,
                      "[Hz] doProcess rate; at least the frame (gyro) rate")
                 .required()
                 .add("max_queue_len", &K::max_queue_len, "observations queued at most (MRPT)")
                 .add("grab_decimation", &K::grab_decimation, "keep 1 of N observations (MRPT)")
                 .add("sensorLabel", &K::sensorLabel, "label of the observations")
                 .add("scenario_file", &K::scenario_file,
                      "scenario .ini played (relative: working dir, else this file's folder)")
                 .required()
                 .add("seed", &K::seed, "run seed; empty = the scenario's seed");
    s.add("truth_label", &K::truth_label,
          cam ? "label of the truth emitted per frame; empty = none"
              : "label of the scenario's attitude truth at its frame times (for frames "
                "from elsewhere: a folder rendered from the scenario); empty = none");
    if (cam)
      s.add("scenario_head", &K::scenario_head,
            "which camera head of the scenario (its head_sections order, 0 = the first) this "
            "camera is");
    if (!cam)
      s.add("velocity_label", &K::velocity_label,
            "label of the scenario's [orbit] velocity samples (CObservationIMU IMU_*_VEL); "
            "empty = none");
    return s;
  };
  static const auto camera_schema = make(true), gyro_schema = make(false);
  return camera ? camera_schema : gyro_schema;
}

bool isSimulatedSensorSection(const mrpt::config::CConfigFileBase& cfg, const std::string& section) {
  const std::string d = cfg.read_string(section, "driver", "", false);
  return d == kCameraDriver || d == kGyroDriver;
}

std::string printSimulatedSensorSection(const IniReader& r, const std::string& section) {
  const bool camera = r.str(section, "driver", "") == kCameraDriver;
  return simulatedSensorSchema(camera).print(section, readKeys(r, section, camera));
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
  const IniReader r{cfg, "", true};  // our message passes through CGenericSensor::loadConfig
  const SimulatedSensorKeys k = readKeys(r, section, true);
  scenario_file_ = resolveScenarioFile(cfg, k.scenario_file);
  seed_ = optionalSeed(r, section, k);
  truth_label_ = k.truth_label;
  head_ = k.scenario_head;
  head_key_ = r.whereKey(section, "scenario_head");
}

const CameraHead& CSimulatedStarCamera::head(const Scenario& sc) const {
  // Checked where the scenario is read (initialize, facts): a bad scenario value is reported
  // there with its own file, section and key.
  if (head_ < 0 || head_ >= static_cast<int>(sc.heads.size()))
    throw InputError(head_key_ + " = " + std::to_string(head_) + ": the scenario has " +
                     std::to_string(sc.heads.size()) + " camera head(s)");
  return sc.heads[static_cast<std::size_t>(head_)];
}

void CSimulatedStarCamera::setPathForExternalImages(const std::string& directory) {
  if (!mrpt::system::createDirectory(directory))
    throw InputError(directory + ": cannot create the external images folder");
  m_path_for_external_images = directory;
}

void CSimulatedStarCamera::initialize() {
  m_state = ssInitializing;
  scenario_ = std::make_unique<Scenario>(Scenario::load(scenario_file_));
  head(*scenario_);
  sim_ = std::make_unique<SkySimulator>(*scenario_, seed_.value_or(scenario_->seed), head_);
  next_frame_ = 0;
  m_state = ssWorking;
}

ImageSourceFacts CSimulatedStarCamera::facts() const {
  const Scenario sc = scenario_ ? *scenario_ : Scenario::load(scenario_file_);
  ImageSourceFacts f;
  f.camera = sc.camera;
  f.exposure_s = sc.sensor.exposure_s;
  f.gain_e_per_adu = sc.sensor.gain();
  f.read_noise_adu = sc.sensor.read_noise_e / sc.sensor.gain();
  f.epoch_jyear = sc.epochJyear();
  f.mount = head(sc).pose();
  return f;
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
  // The scenario's clock, not the wall clock: the sky was rendered for the scenario's date,
  // and a recording replays with a star database of its stamps' epoch.
  const auto stamp = sc.timestamp(f.stamp_t);  // the camera's clock (faults.hpp: jumps)
  std::vector<mrpt::serialization::CSerializable::Ptr> out;
  if (!f.dropped) {
    auto obs = makeCameraObservation(f.image, sc.camera, stamp, m_sensorLabel, sim_->mount());
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
  if (!truth_label_.empty()) {
    FrameTruth truth;
    truth.q_ib = f.q_ib;
    for (const TrueStar& s : f.truth) truth.stars.push_back({s.id, s.px, s.mag, head_});
    out.push_back(makeTruthObservation(truth, stamp, truth_label_));
  }
  if (!out.empty()) appendObservations(out);
}

// ---- gyro -----------------------------------------------------------------------------

CSimulatedGyro::CSimulatedGyro() { m_sensorLabel = kGyroLabel; }
CSimulatedGyro::~CSimulatedGyro() = default;

void CSimulatedGyro::loadConfig_sensorSpecific(const mrpt::config::CConfigFileBase& cfg,
                                               const std::string& section) {
  const IniReader r{cfg, "", true};  // our message passes through CGenericSensor::loadConfig
  const SimulatedSensorKeys k = readKeys(r, section, false);
  scenario_file_ = resolveScenarioFile(cfg, k.scenario_file);
  seed_ = optionalSeed(r, section, k);
  truth_label_ = k.truth_label;
  velocity_label_ = k.velocity_label;
}

void CSimulatedGyro::initialize() {
  m_state = ssInitializing;
  scenario_ = std::make_unique<Scenario>(Scenario::load(scenario_file_));
  if (!scenario_->gyro)
    throw InputError(scenario_file_ + ": the scenario has no [gyro] section for CSimulatedGyro");
  stream_ = std::make_unique<GyroStream>(*scenario_, seed_.value_or(scenario_->seed));
  next_truth_ = 0;
  velocity_.reset();
  if (!velocity_label_.empty()) velocity_ = std::make_unique<VelocityStream>(*scenario_);
  done_ = false;
  m_state = ssWorking;
}

void CSimulatedGyro::doProcess() {
  if (!stream_ || done_) return;
  const double now = simulatedSensorsElapsed();
  // The velocity is known ahead (an orbit propagator's): due ones go first, so the frame at
  // t = 0 already has the sample of t = 0, as in `simulate`.
  appendVelocitiesUpTo(now);
  GyroSample g;
  while (stream_->nextTime() <= now) {
    if (!stream_->next(g)) {
      done_ = true;
      break;
    }
    appendTruthsUpTo(g.t);
    appendObservation(makeGyroObservation(g.rate, scenario_->timestamp(g.t), m_sensorLabel));
    ++emitted_;
  }
  if (stream_->nextTime() > scenario_->duration_s + 1e-9) done_ = true;
  if (done_) {
    appendTruthsUpTo(scenario_->duration_s);
    appendVelocitiesUpTo(scenario_->duration_s);
  }
}

void CSimulatedGyro::appendVelocitiesUpTo(double t) {
  VelocitySample v;
  while (velocity_ && velocity_->nextTime() <= t + 1e-12 && velocity_->next(v))
    appendObservation(makeVelocityObservation(v.velocity_km_s, scenario_->timestamp(v.t),
                                              velocity_label_));
}

void CSimulatedGyro::appendTruthsUpTo(double t) {
  if (truth_label_.empty()) return;
  const Scenario& sc = *scenario_;
  // The attitude only (no rendered stars): identities cannot be scored from it. On the
  // scenario's clock without its camera-clock faults: the truth is of the motion.
  for (; next_truth_ < sc.frameCount() && sc.frameTime(next_truth_) <= t; ++next_truth_) {
    const double tk = sc.frameTime(next_truth_);
    appendObservation(makeTruthObservation(canonical(sc.motion->attitude(tk)), {},
                                           sc.timestamp(tk), truth_label_));
  }
}

}  // namespace st

#include "sensors/mrpt/star_tracker_sensor.hpp"

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/hwdrivers/CCameraSensor.h>
#include <mrpt/obs/CObservationImage.h>
#include <mrpt/system/filesystem.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <opencv2/imgproc.hpp>

#include "catalog/star_catalog.hpp"
#include "catalog/star_database.hpp"
#include "common/conventions.hpp"
#include "common/errors.hpp"
#include "common/mrpt_convert.hpp"
#include "config/ini_reader.hpp"
#include "sensors/mrpt/star_tracker_sensor_ini.hpp"
#include "sensors/sim/scenario.hpp"
#include "sensors/sim/simulated_sensors.hpp"

IMPLEMENTS_GENERIC_SENSOR(CStarTrackerSensor, st)

namespace st {

namespace {

bool endsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

}  // namespace

void registerStarTrackerSensor() { CStarTrackerSensor::doRegister(); }

CStarTrackerSensor::CStarTrackerSensor() { m_sensorLabel = "STAR_TRACKER"; }
CStarTrackerSensor::~CStarTrackerSensor() = default;

void CStarTrackerSensor::loadConfig_sensorSpecific(const mrpt::config::CConfigFileBase& cfg,
                                                   const std::string& section) {
  section_ = section;
  const IniReader r{cfg, "", true};
  auto str = [&](const std::string& k) { return r.str(section, k, ""); };

  // The whole section, strictly, once (star_tracker_sensor_ini.hpp); the image source made
  // below reads its own keys again.
  const StarTrackerSensorKeys keys = readStarTrackerSensorKeys(r, section);

  // --- image source ---
  source_kind_ = keys.image_source;
  image_label_ = keys.image_label;
  emit_image_ = keys.emit_image;
  camera_file_ = keys.camera_file;
  camera_file_section_ = keys.camera_file_section;
  if (source_kind_ == "simulated") {
    scenario_file_ = str("scenario_file");
    if (scenario_file_.empty()) throw InputError(r.where(section, "scenario_file") + ": missing key");
    if (!mrpt::system::fileExists(scenario_file_)) {
      throw InputError(r.where(section, "scenario_file") + ": no such file '" + scenario_file_ + "'");
    }
    auto sim = std::make_unique<CSimulatedStarCamera>();
    sim->loadConfig(cfg, section);
    source_ = std::move(sim);
  } else if (source_kind_ == "camera") {
    if (camera_file_.empty()) {
      throw InputError(r.where(section, "camera_file") +
                       ": missing key (the calibration is needed with image_source = camera)");
    }
    std::string cam_section = section;
    cam_section = r.str(section, "camera_section", cam_section);
    if (!cfg.sectionExists(cam_section)) {
      throw InputError(r.where(section, "camera_section") + ": no section '" + cam_section + "'");
    }
    auto cam = std::make_unique<mrpt::hwdrivers::CCameraSensor>();
    cam->loadConfig(cfg, cam_section);
    source_ = std::move(cam);
  } else {
    throw InputError(r.where(section, "image_source") + ": unknown value '" + source_kind_ +
                     "' (simulated | camera)");
  }
  if (source_) source_->setSensorLabel(image_label_);
  if (!camera_file_.empty() && !mrpt::system::fileExists(camera_file_)) {
    throw InputError(r.where(section, "camera_file") + ": no such file '" + camera_file_ + "'");
  }

  // --- star database ---
  database_file_ = keys.database_file;
  catalog_file_ = keys.catalog_file;
  mag_limit_ = keys.mag_limit;
  aberration_ = keys.aberration;
  if (keys.epoch_jyear != 0) epoch_jyear_ = keys.epoch_jyear;
  if (!database_file_.empty() && !mrpt::system::fileExists(database_file_)) {
    throw InputError(r.where(section, "database_file") + ": no such file '" + database_file_ + "'");
  }
  if (!catalog_file_.empty() && !mrpt::system::fileExists(catalog_file_)) {
    throw InputError(r.where(section, "catalog_file") + ": no such file '" + catalog_file_ + "'");
  }

  // --- pipeline ---
  PipelineOptions o;
  o.tracker = keys.tracker;
  o.sensor_label = m_sensorLabel;
  has_exposure_ = r.has(section, "exposure_s");
  has_gain_ = r.has(section, "gain_e_per_adu");
  has_read_noise_ = r.has(section, "read_noise_adu");
  opts_ = o;
}

void CStarTrackerSensor::setPathForExternalImages(const std::string& directory) {
  std::error_code ec;  // mrpt::system::createDirectory fails when the folder exists
  std::filesystem::create_directories(directory, ec);
  if (ec) throw InputError(directory + ": cannot create the external images folder: " + ec.message());
  m_path_for_external_images = directory;
}

void CStarTrackerSensor::initialize() {
  m_state = ssInitializing;
  if (!source_) throw InputError("CStarTrackerSensor: initialize() before loadConfig()");
  const std::string& s = section_;
  std::optional<Scenario> scenario;
  if (source_kind_ == "simulated") scenario = Scenario::load(scenario_file_);

  // Camera model: the file, else the simulated scenario's camera.
  if (!camera_file_.empty()) {
    try {
      if (endsWith(camera_file_, ".yaml") || endsWith(camera_file_, ".yml") ||
          endsWith(camera_file_, ".xml")) {
        camera_ = CameraModel::loadYaml(camera_file_);
      } else {
        camera_ = CameraModel::loadIniFile(camera_file_, camera_file_section_);
      }
    } catch (const InputError& e) {
      throw InputError("section '" + s + "' key 'camera_file': " + e.what());
    }
  } else {
    camera_ = scenario->camera;
  }

  PipelineOptions o = opts_;
  o.sensor_label = m_sensorLabel;
  if (scenario) {  // the detector's noise model must match the simulated sensor
    TrackerOptions& t = o.tracker;
    if (!has_exposure_) t.exposure_s = scenario->sensor.exposure_s;
    if (!has_gain_) t.detect.gain_e_per_adu = scenario->sensor.gain();
    if (!has_read_noise_) {
      t.detect.read_noise_adu = scenario->sensor.read_noise_e / scenario->sensor.gain();
    }
  }
  opts_ = o;

  // Star database: a file, or built in memory for this camera.
  try {
    if (!database_file_.empty()) {
      db_ = std::make_shared<const StarDatabase>(StarDatabase::load(database_file_));
    } else {
      DatabaseParams p{};
      p.max_pair_angle = 2.0 * camera_.halfDiagonalFov() + deg2rad(0.5);
      p.mag_limit = mag_limit_;
      p.epoch_jyear = epoch_jyear_ ? *epoch_jyear_
                      : scenario   ? scenario->epochJyear()
                                   : julianYear(mrpt::Clock::now());
      p.aberration = aberration_;
      p.double_star_sep = arcsec2rad(10.0);
      p.max_stars_per_region = 0;
      p.neighbour_radius = deg2rad(5.0);
      const std::string cat =
          catalog_file_.empty() ? StarDatabase::defaultCatalogPath() : catalog_file_;
      db_ = std::make_shared<const StarDatabase>(StarDatabase::build(loadCatalog(cat), p));
    }
    tracker_ = std::make_unique<StarTracker>(*db_, camera_, o.trackerOptions());
  } catch (const InputError& e) {
    throw InputError("section '" + s + "': " + e.what());
  }

  source_->initialize();
  m_state = ssWorking;
}

bool CStarTrackerSensor::sourceFinished() const {
  const auto* sim = dynamic_cast<const CSimulatedStarCamera*>(source_.get());
  return sim && sim->finished();
}

void CStarTrackerSensor::setInputsProvider(InputsProvider provider) {
  std::lock_guard<std::mutex> lock(mutex_);
  provider_ = std::move(provider);
}

CObservationStarTracker::Ptr CStarTrackerSensor::lastObservation() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return last_obs_;
}

cv::Mat CStarTrackerSensor::lastImage() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return last_image_;
}

void CStarTrackerSensor::doProcess() {
  if (!source_ || !tracker_) return;
  source_->doProcess();
  TListObservations in;
  source_->getObservations(in);
  std::vector<mrpt::serialization::CSerializable::Ptr> out;
  for (auto& [t, obj] : in) {
    auto img = std::dynamic_pointer_cast<mrpt::obs::CObservationImage>(obj);
    if (!img) {  // e.g. the simulated camera's GROUND_TRUTH: pass it on
      out.push_back(obj);
      continue;
    }
    cv::Mat frame = img->image.asCvMat<cv::Mat>(mrpt::img::SHALLOW_COPY);
    if (frame.channels() == 3) {
      cv::Mat grey;
      cv::cvtColor(frame, grey, cv::COLOR_BGR2GRAY);
      frame = grey;
    }
    processFrame(*img, frame, out);
    if (emit_image_) {
      if (!m_path_for_external_images.empty()) {
        char name[128];
        std::snprintf(name, sizeof(name), "%s_%06d.%s", img->sensorLabel.c_str(), image_counter_++,
                      m_external_images_format.c_str());
        img->image.saveToFile(m_path_for_external_images + "/" + name);
        img->image.setExternalStorage(name);
      }
      out.insert(out.end() - 1, img);  // the frame before its fix
    }
  }
  if (!out.empty()) appendObservations(out);
}

void CStarTrackerSensor::processFrame(const mrpt::obs::CObservation& image_obs,
                                      const cv::Mat& image,
                                      std::vector<mrpt::serialization::CSerializable::Ptr>& out) {
  const mrpt::Clock::time_point t = image_obs.timestamp;
  InputsProvider provider;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    provider = provider_;
  }
  // Called without our lock: it may take the caller's.
  const FrameInputs inputs = provider ? provider(t) : FrameInputs{};
  if (!first_frame_) first_frame_ = t;
  const double t_s = std::chrono::duration<double>(t - *first_frame_).count();
  const FrameResult frame = tracker_->process(image, t_s, inputs);
  auto obs = observationFromFrame(frame, t, m_sensorLabel, opts_.sensor_pose);
  ++frames_;
  if (obs->hasAttitude()) ++solved_;
  if (obs->mode == StarTrackerMode::kTracking) ++tracking_;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    last_obs_ = obs;
    last_image_ = image.clone();
  }
  out.push_back(obs);
}

}  // namespace st

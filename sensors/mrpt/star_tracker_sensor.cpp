#include "sensors/mrpt/star_tracker_sensor.hpp"

#include "catalog/database_cache.hpp"

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/hwdrivers/CCameraSensor.h>
#include <mrpt/obs/CObservationImage.h>
#include <mrpt/system/datetime.h>
#include <mrpt/system/filesystem.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <opencv2/imgproc.hpp>

#include "catalog/star_catalog.hpp"
#include "catalog/star_database.hpp"
#include "common/conventions.hpp"
#include "common/errors.hpp"
#include "common/mrpt_convert.hpp"
#include "common/utc_time.hpp"
#include "config/ini_reader.hpp"
#include "catalog/database_recipe.hpp"
#include "sensors/mrpt/image_source.hpp"
#include "sensors/mrpt/star_tracker_sensor_ini.hpp"
#include "sensors/mrpt/camera_ini.hpp"

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
    // The simulator is its own plugin: the production sensor creates it by name through
    // MRPT's factory and never links it.
    source_.reset(mrpt::hwdrivers::CGenericSensor::createSensor(kSimulatedCameraClass));
    if (!source_) {
      throw InputError(r.where(section, "image_source") + " = simulated: the sensor class " +
                       kSimulatedCameraClass +
                       " is not registered (load the simulator plugin, e.g. rawlog-grabber -p "
                       "libstartracker_mrpt.so,libstartracker_sim.so)");
    }
    source_->loadConfig(cfg, section);
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
    readFrameClock(r, section, keys);
    auto cam = std::make_unique<mrpt::hwdrivers::CCameraSensor>();
    cam->loadConfig(cfg, cam_section);
    source_ = std::move(cam);
  } else {
    throw InputError(r.where(section, "image_source") + ": unknown value '" + source_kind_ +
                     "' (simulated | camera)");
  }
  if (source_kind_ != "camera" && (keys.frame_rate_hz != 0 || !keys.frame_start_time.empty()))
    throw InputError(r.where(section, keys.frame_rate_hz != 0 ? "frame_rate_hz" : "frame_start_time") +
                     ": only with image_source = camera (a simulated camera stamps its "
                     "scenario's clock)");
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
  if (r.has(section, "mount_ypr_deg")) mount_ypr_deg_ = keys.mount_ypr_deg;
  opts_ = o;
}

void CStarTrackerSensor::readFrameClock(const IniReader& r, const std::string& section,
                                        const StarTrackerSensorKeys& keys) {
  frame_rate_hz_ = keys.frame_rate_hz;
  frame_start_unix_s_.reset();
  if (!std::isfinite(frame_rate_hz_) || frame_rate_hz_ < 0)
    throw InputError(r.where(section, "frame_rate_hz") + ": must be >= 0 (0 = the grabber's clock)");
  if (keys.frame_start_time.empty()) return;
  if (frame_rate_hz_ == 0)
    throw InputError(r.where(section, "frame_start_time") + ": needs frame_rate_hz > 0");
  frame_start_unix_s_ = parseUtc(keys.frame_start_time, r.where(section, "frame_start_time"));
  // The sky of a recording is the recording's: its date is the database's epoch unless the
  // section sets one.
  if (keys.epoch_jyear == 0) epoch_jyear_ = julianYearFromUnixSeconds(*frame_start_unix_s_);
}

void CStarTrackerSensor::restamp(mrpt::obs::CObservationImage& img) {
  if (frame_rate_hz_ <= 0) return;
  if (!frame_start_unix_s_) frame_start_unix_s_ = mrpt::Clock::toDouble(img.timestamp);
  // k / rate as a scenario computes its frame times: a folder rendered from one replays on
  // its clock to the tick (the simulated gyro and truth beside it).
  img.timestamp = timestampAfter(*frame_start_unix_s_, clock_frames_++ / frame_rate_hz_);
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
  // What the source knows (a simulated camera: its optics, noise and epoch).
  ImageSourceFacts facts;
  if (const auto* src = dynamic_cast<const StarImageSource*>(source_.get())) {
    try {
      facts = src->facts();
    } catch (const InputError& e) {
      throw InputError("section '" + s + "': " + e.what());
    }
  }

  // Camera model: the file, else the simulated scenario's camera.
  if (!camera_file_.empty()) {
    try {
      if (endsWith(camera_file_, ".yaml") || endsWith(camera_file_, ".yml") ||
          endsWith(camera_file_, ".xml")) {
        camera_ = CameraModel::loadYaml(camera_file_);
      } else {
        camera_ = loadCameraIniFile(camera_file_, camera_file_section_);
      }
    } catch (const InputError& e) {
      throw InputError("section '" + s + "' key 'camera_file': " + e.what());
    }
  } else if (facts.camera) {
    camera_ = *facts.camera;
  } else {
    throw InputError("section '" + s + "' key 'camera_file': missing (the image source does "
                     "not know its camera)");
  }

  PipelineOptions o = opts_;
  o.sensor_label = m_sensorLabel;
  // The detector's noise model must match the source's sensor where the keys leave it open.
  TrackerOptions& t = o.tracker;
  if (!has_exposure_ && facts.exposure_s) t.exposure_s = *facts.exposure_s;
  if (!has_gain_ && facts.gain_e_per_adu) t.detect.gain_e_per_adu = *facts.gain_e_per_adu;
  if (!has_read_noise_ && facts.read_noise_adu) t.detect.read_noise_adu = *facts.read_noise_adu;
  // The mounting: the section's, else what the source knows (a simulated head's).
  if (mount_ypr_deg_) {
    o.sensor_pose = mountingPose(*mount_ypr_deg_);
  } else if (facts.mount) {
    o.sensor_pose = *facts.mount;
  }
  opts_ = o;

  // Star database: a file, or built in memory for this camera.
  db_build_ = DatabaseBuild{database_file_, catalog_file_, mag_limit_, 0.0, aberration_};
  try {
    if (!database_file_.empty()) {
      db_ = std::make_shared<const StarDatabase>(StarDatabase::load(database_file_));
    } else {
      CameraDatabaseRecipe recipe;  // the one recipe of solve and replay
      recipe.diagonal_fov_rad = 2.0 * camera_.halfDiagonalFov();
      recipe.pixel_scale_rad = camera_.pixelScale();
      recipe.mag_limit = mag_limit_;
      recipe.epoch_jyear = epoch_jyear_         ? *epoch_jyear_
                           : facts.epoch_jyear ? *facts.epoch_jyear
                                               : julianYear(mrpt::Clock::now());
      recipe.aberration = aberration_;
      db_build_.epoch_jyear = recipe.epoch_jyear;
      db_ = cameraDatabase(recipe, catalog_file_);
    }
    tracker_ = std::make_unique<StarTracker>(*db_, camera_, o.trackerOptions());
  } catch (const InputError& e) {
    throw InputError("section '" + s + "': " + e.what());
  }

  source_->initialize();
  m_state = ssWorking;
}

bool CStarTrackerSensor::sourceFinished() const {
  if (camera_finished_) return true;
  const auto* src = dynamic_cast<const StarImageSource*>(source_.get());
  return src && src->finished();
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
  if (!source_ || !tracker_ || camera_finished_) return;
  try {
    source_->doProcess();
  } catch (const std::exception& e) {
    // MRPT's image_dir grabber throws at the end of its folder (end_index): the end of the
    // frames, not a failure of the camera.
    if (source_kind_ != "camera" || std::string(e.what()).find("Reached end index") == std::string::npos)
      throw;
    camera_finished_ = true;
    return;
  }
  TListObservations in;
  source_->getObservations(in);
  std::vector<mrpt::serialization::CSerializable::Ptr> out;
  for (auto& [t, obj] : in) {
    auto img = std::dynamic_pointer_cast<mrpt::obs::CObservationImage>(obj);
    if (!img) {  // e.g. the simulated camera's GROUND_TRUTH: pass it on
      out.push_back(obj);
      continue;
    }
    if (source_kind_ == "camera") restamp(*img);
    processFrame(*img, img->image.asCvMat<cv::Mat>(mrpt::img::SHALLOW_COPY), out);
    if (emit_image_) {
      // The frame carries the mounting the tracker used: replay mounts its tracker by it.
      img->cameraPose = opts_.sensor_pose;
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

void CStarTrackerSensor::updateCameraReport() {
  const auto& fit = tracker_->cameraFit();
  if (!fit) return;
  const std::string name = camera_file_.empty() ? "the configured camera" : camera_file_;
  std::string d = describeDiscrepancy(*fit, camera_, name);
  char b[200];
  int n = std::snprintf(b, sizeof b, "camera: fx %.2f +- %.2f px", fit->theta[kFx], fit->sigma(kFx));
  if (fit->sigma(kK1) > 0)
    n += std::snprintf(b + n, sizeof b - n, ", k1 %.4f +- %.4f", fit->theta[kK1], fit->sigma(kK1));
  std::snprintf(b + n, sizeof b - n, ", model error %.3f px", tracker_->modelErrorPx());
  std::string report = b;
  if (!d.empty()) report += "; " + d + "; run `startracker calibrate` on frames of this camera";
  std::lock_guard<std::mutex> lock(mutex_);
  camera_report_ = std::move(report);
}

std::string CStarTrackerSensor::cameraReport() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return camera_report_;
}

void CStarTrackerSensor::processFrame(mrpt::obs::CObservationImage& image_obs,
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
  // As the navigator counts time (replay's tracker gets its seconds): the same frames then
  // give the same numbers live and in replay.
  const double t_s = mrpt::system::timeDifference(*first_frame_, t);
  // The frame is recorded with the camera it was processed with (replay starts from the
  // first frame's and refines as this run did).
  image_obs.cameraParams = toTCamera(tracker_->camera());
  const FrameResult frame = st::processFrame(*tracker_, frozen_, image, t_s, inputs);
  if (frame.camera_updated) updateCameraReport();
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

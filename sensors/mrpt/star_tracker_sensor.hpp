/// @file star_tracker_sensor.hpp
/// `st::CStarTrackerSensor`: the star tracker as an MRPT sensor (CGenericSensor), so that
/// rawlog-grabber (with the startracker_mrpt plugin) and `startracker live` run it like any
/// other MRPT sensor. Each doProcess() polls an inner image source (an MRPT CCameraSensor or
/// the simulated star camera), runs the StarTracker (sensors/tracking/) on every new frame and
/// emits one CObservationStarTracker per frame (label = sensorLabel, default STAR_TRACKER),
/// plus the frame itself (CObservationImage, optional) and whatever else the source emits (the
/// simulated camera's GROUND_TRUTH).
///
/// .ini section (besides CGenericSensor's process_rate [required], sensorLabel, ...):
///   driver        = CStarTrackerSensor
///   image_source  = simulated | camera                     (required)
///     simulated:  scenario_file = path (required), seed, truth_label: the keys of
///                 CSimulatedStarCamera (sensors/sim/simulated_sensors.hpp), read from this
///                 same section. Camera, exposure and detector noise default to the scenario.
///     camera:     camera_section = SECTION (default: this section) with the keys of
///                 mrpt::hwdrivers::CCameraSensor (grabber_type = opencv | ffmpeg |
///                 image_dir | ..., cv_camera_index, ffmpeg_url, image_dir_url, ...).
///                 frame_rate_hz, frame_start_time: a recording (an image folder, a video)
///                 is stamped on its own clock, frame k at start + k / rate, instead of
///                 when the grabber reads it (MRPT's grabbers stamp the wall clock); the
///                 start's date is then the database's epoch unless epoch_jyear is set.
///     simulated with several camera heads: scenario_head = N (the scenario's head N; its
///                 frames carry that head's mounting as cameraPose).
///   mount_ypr_deg = y p r         the camera's mounting on the body [deg], MRPT CPose3D yaw
///                                 pitch roll of body-from-camera: the tracker's R_body_cam and
///                                 the sensor pose of its observations (default: a simulated
///                                 head's own mounting, else identity)
///   image_label   = CAMERA        label of the emitted frames
///   emit_image    = true          also emit the frames (external PNGs when the grabber sets
///                                 an external images path, as rawlog-grabber does)
///   camera_file   = path          CameraModel: .yaml/.yml/.xml (OpenCV) or an .ini with a
///                                 TCamera section `camera_file_section` (default "camera").
///                                 Required for image_source = camera.
///   database_file = path          a StarDatabase file; if empty one is built in memory from
///   catalog_file  = path          (default StarDatabase::defaultCatalogPath()) with
///   mag_limit = 6.5, epoch_jyear (default: the scenario's epoch, else required),
///   aberration = true
///   Tracker: the keys of pipeline_ini.hpp (stage-prefixed: detect_, lis_, verify_, track_,
///   f2f_), as in the navigator's [pipeline]. The section is strict: star_tracker_sensor_ini.hpp.
///   Relative paths are taken as they are (relative to the working directory).
///
/// Errors: a missing or bad key throws st::InputError ("section 'S' key 'K': ..."), from
/// loadConfig() (cheap checks) or initialize() (files, algorithm names). Note that
/// CGenericSensor::loadConfig wraps exceptions in MRPT's stacked exception (the message is
/// kept, the type is not).
///
/// Threads: doProcess() runs in the grabber's thread; setInputsProvider() and the statistics
/// may be called from any other thread.
#pragma once
#include <mrpt/core/Clock.h>
#include <mrpt/hwdrivers/CGenericSensor.h>
#include <mrpt/obs/CObservationImage.h>

#include <atomic>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "sensors/camera/camera_model.hpp"
#include "sensors/mrpt/image_source.hpp"
#include "sensors/mrpt/observation_from_frame.hpp"
#include "sensors/tracking/frozen_frame.hpp"
#include "sensors/tracking/star_tracker.hpp"

namespace st {

class StarDatabase;
struct IniReader;
struct StarTrackerSensorKeys;

class CStarTrackerSensor : public mrpt::hwdrivers::CGenericSensor, public FiniteSensor {
  DEFINE_GENERIC_SENSOR(CStarTrackerSensor)
 public:
  /// Called from the sensor's thread with a frame's timestamp before the frame is processed;
  /// returns what the outside knows at that time (a prediction, a rate, or nothing: then
  /// frame-to-frame / lost-in-space).
  using InputsProvider = std::function<FrameInputs(mrpt::Clock::time_point frame_time)>;

  CStarTrackerSensor();
  ~CStarTrackerSensor() override;

  void initialize() override;
  void doProcess() override;
  void setPathForExternalImages(const std::string& directory) override;

  /// The source of each frame's FrameInputs, asked at the frame's time (e.g. a filter's
  /// prediction); an empty function removes it. The function runs in the sensor's thread.
  void setInputsProvider(InputsProvider provider);

  /// Statistics (thread-safe).
  int framesProcessed() const { return frames_; }
  int framesSolved() const { return solved_; }
  int framesTracking() const { return tracking_; }
  /// The last star-tracker observation and frame (nullptr before the first frame).
  CObservationStarTracker::Ptr lastObservation() const;
  cv::Mat lastImage() const;

  /// One line on the camera model in force (thread-safe): the tracker's last online or healing
  /// fit against the camera file (its discrepancy, `startracker calibrate` advice) and the
  /// camera-model error term; "" before any fit.
  std::string cameraReport() const;

  /// Available after initialize(): the configured camera (the file's). The model in force,
  /// refined online, is recorded with every emitted frame (CObservationImage::cameraParams).
  const CameraModel& camera() const { return camera_; }
  const StarDatabase* database() const { return db_.get(); }
  /// The tracker's effective options (the source's exposure and noise filled in).
  const PipelineOptions& pipelineOptions() const { return opts_; }
  /// How the star database was made: what a replay needs to make the same one.
  struct DatabaseBuild {
    std::string file;     ///< a saved database (as configured); empty = built from:
    std::string catalog;  ///< as configured; empty = StarDatabase::defaultCatalogPath()
    double mag_limit = 6.5;
    double epoch_jyear = 0;  ///< the epoch used (the key's, the source's, or now)
    bool aberration = true;
  };
  const DatabaseBuild& databaseBuild() const { return db_build_; }
  const std::string& imageLabel() const { return image_label_; }
  /// True when the inner source has no more frames (a finished simulated scenario, the end of
  /// an image_dir grabber's folder).
  bool sourceFinished() const;
  bool finished() const override { return sourceFinished(); }  ///< FiniteSensor

 protected:
  void loadConfig_sensorSpecific(const mrpt::config::CConfigFileBase& cfg,
                                 const std::string& section) override;

 private:
  void processFrame(mrpt::obs::CObservationImage& image_obs, const cv::Mat& image,
                    std::vector<mrpt::serialization::CSerializable::Ptr>& out);
  void updateCameraReport();
  /// The frame_rate_hz / frame_start_time keys: a recording played by the grabber is stamped
  /// on its own clock (frame k at start + k / rate), not when it is read.
  void readFrameClock(const IniReader& r, const std::string& section,
                      const StarTrackerSensorKeys& keys);
  void restamp(mrpt::obs::CObservationImage& img);

  // configuration
  std::string section_;
  std::string source_kind_;  // "simulated" | "camera"
  double frame_rate_hz_ = 0;  // 0: the grabber's stamps
  std::optional<double> frame_start_unix_s_;
  int clock_frames_ = 0;
  std::string image_label_ = "CAMERA";
  bool emit_image_ = true;
  std::string camera_file_, camera_file_section_ = "camera";
  std::string database_file_, catalog_file_;
  double mag_limit_ = 6.5;
  std::optional<double> epoch_jyear_;
  bool aberration_ = true;
  PipelineOptions opts_;
  // which pipeline/detector keys the .ini set (the rest default to the scenario's values)
  bool has_exposure_ = false, has_gain_ = false, has_read_noise_ = false;
  std::optional<Vec3> mount_ypr_deg_;  // written in the section
  std::string scenario_file_;

  // runtime
  std::unique_ptr<mrpt::hwdrivers::CGenericSensor> source_;
  std::atomic<bool> camera_finished_{false};
  std::shared_ptr<const StarDatabase> db_;
  DatabaseBuild db_build_;
  CameraModel camera_;
  std::unique_ptr<StarTracker> tracker_;
  FrozenFrameCheck frozen_;  // a repeated readout is not processed (frozen_frame.hpp)
  int image_counter_ = 0;
  /// The tracker's time: seconds from the first frame (it only takes differences).
  std::optional<mrpt::Clock::time_point> first_frame_;

  mutable std::mutex mutex_;  // guards everything below
  InputsProvider provider_;
  CObservationStarTracker::Ptr last_obs_;
  cv::Mat last_image_;
  std::string camera_report_;
  std::atomic<int> frames_{0}, solved_{0}, tracking_{0};
};

/// Registers CStarTrackerSensor with MRPT's sensor factory (idempotent).
void registerStarTrackerSensor();

}  // namespace st

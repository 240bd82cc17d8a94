/// @file scenario.hpp
/// A simulation scenario (.ini) and the sky simulator that plays it: one clock, the true
/// motion, the star camera (renderer + detector + faults) and the gyro. The same model is
/// used by `startracker simulate` (offline, to a rawlog) and by the live MRPT sensors
/// CSimulatedStarCamera / CSimulatedGyro, so both give the same data for a seed.
///
/// Scenario .ini (sections and keys; rates in deg/s, times in s):
///   [scenario]
///     duration_s = 10          run length; frames at t_k = k / frame_rate_hz, k = 0.. while
///     frame_rate_hz = 10       t_k < duration_s; t_k is the mid-exposure time
///     start_time = 2025-03-20T00:00:00   UTC of t = 0 (also the catalog epoch); or
///     start_jyear = 2025.2     the same as a Julian year
///     seed = 1                 default run seed (the CLI's --seed overrides it)
///     database =               a database file (StarDatabase::save); empty = build one in
///                              memory from `catalog` (default StarDatabase::defaultCatalogPath())
///     catalog =                catalog for the in-memory build
///     mag_limit = 6.6          faintest star rendered (in-memory build; capped, with a
///                              warning, at the catalog's depth: V 6.6 for the default one)
///     aberration = true        apparent places (annual aberration), in-memory build
///     camera_section = camera, sensor_section = sensor, motion_section = motion,
///     gyro_section = gyro (absent section = no gyro), faults_section = faults,
///     orbit_section = orbit (absent section = no orbit: no aberration of the observer's own
///     motion)
///     head_sections =          several camera heads: one section per head, comma-separated (empty = one head,
///                              CAMERA, along the body's +z)
///   [<head>]   label = CAMERA2 (its images' rawlog label), mount_ypr_deg = yaw pitch roll
///              (MRPT CPose3D angles of body-from-camera, written as the images' cameraPose),
///              faults_section (its camera faults: blinding, drops, frozen images, clock;
///              default the scenario's). Every head has the scenario's camera and sensor.
///   [camera]   CameraModel::loadIni keys: resolution = [w h] with either fx, fy, cx, cy
///              or fov_deg (horizontal); optional dist
///   [sensor]   SensorParams keys (sensor_params.hpp)
///   [motion]   MotionProfile keys (motion.hpp)
///   [gyro]     GyroParams keys (gyro_model.hpp) plus initial_bias_deg_h = x y z (turn-on
///              bias, default 0 0 0)
///   [faults]   FaultParams keys (faults.hpp)
///   [orbit]    CircularOrbit keys (orbit.hpp): the sky is rendered aberrated by the orbit's
///              velocity, and VELOCITY observations carry it (velocity_rate_hz)
/// Relative paths (database, catalog) are relative to the scenario file's folder.
/// Every section is read strictly (config/schema.hpp): an unknown key is an error naming
/// the file, section and key, with the nearest valid key.
#pragma once
#include <mrpt/core/Clock.h>
#include <mrpt/poses/CPose3D.h>

#include <memory>
#include <opencv2/core.hpp>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "sensors/camera/camera_model.hpp"
#include "sensors/sim/detector.hpp"
#include "sensors/sim/faults.hpp"
#include "sensors/sim/gyro_model.hpp"
#include "sensors/sim/motion.hpp"
#include "sensors/sim/orbit.hpp"
#include "sensors/sim/sensor_params.hpp"
#include "sensors/sim/star_renderer.hpp"
#include "sensors/sim/star_source.hpp"

namespace mrpt::config {
class CConfigFileBase;
}

namespace st {

class StarDatabase;

/// The keys of the [scenario] section, as written in the file.
struct ScenarioKeys {
  double duration_s = 10, frame_rate_hz = 10;
  std::string start_time;  ///< empty = use start_jyear
  double start_jyear = 2025.0;
  uint64_t seed = 1;
  std::string database, catalog;  ///< as written (relative to the file's folder)
  double mag_limit = 6.6;
  bool aberration = true;
  std::string camera_section = "camera", sensor_section = "sensor", motion_section = "motion",
              gyro_section = "gyro", faults_section = "faults", orbit_section = "orbit";
  std::vector<std::string> head_sections;
};

/// A [<head>] section as written.
struct HeadKeys {
  std::string label;
  Vec3 mount_ypr_deg = Vec3::Zero();
  std::string faults_section;  ///< empty = the scenario's faults_section
};

/// One camera head of a scenario: its label, mounting and camera faults.
struct CameraHead {
  std::string label = "CAMERA";
  Vec3 mount_ypr_deg = Vec3::Zero();  ///< [deg] MRPT yaw pitch roll of body-from-camera
  Mat3 R_body_cam = Mat3::Identity();
  std::optional<FaultParams> faults;  ///< its camera faults (none: the scenario's `faults`)
  /// The mounting as an MRPT pose (the cameraPose of its images).
  mrpt::poses::CPose3D pose() const;
};

/// The [gyro] section: GyroParams plus the run's turn-on bias.
struct ScenarioGyroKeys {
  GyroParams params;
  Vec3 initial_bias_deg_h = Vec3::Zero();
};

/// A whole scenario file as read (strictly) from its sections: what `startracker config`
/// prints. The camera is kept resolved (fov_deg turned into fx fy cx cy).
struct ScenarioIni {
  ScenarioKeys main;
  CameraModel camera;
  SensorParams sensor;
  MotionKeys motion;
  std::optional<ScenarioGyroKeys> gyro;
  FaultParams faults;
  std::optional<CircularOrbit> orbit;
  std::vector<HeadKeys> heads;  ///< in head_sections order
  /// Each head's camera faults as read from its faults_section (the scenario's when empty).
  std::vector<FaultParams> head_faults;
};
ScenarioIni readScenarioIni(const IniReader& r);
/// The sections a scenario owns: [scenario] and the sections its keys name (their default
/// names too, present or not: a misspelt [gyr] is then refused, not read as "no gyro").
std::set<std::string> scenarioSectionNames(const IniReader& r);
/// The effective scenario in ini form, every default filled in; reads back to `sc`.
std::string printScenarioIni(const ScenarioIni& sc);

struct Scenario {
  std::string source = "scenario";  ///< file name, for messages
  double duration_s = 10;
  double frame_rate_hz = 10;
  double start_unix_s = 0;          ///< UTC of t = 0 as Unix seconds
  uint64_t seed = 1;
  std::string database_path, catalog_path;
  double mag_limit = 6.6;
  bool aberration = true;
  CameraModel camera;
  SensorParams sensor;
  FaultParams faults;
  std::shared_ptr<const MotionProfile> motion;
  std::optional<GyroParams> gyro;
  Vec3 gyro_initial_bias_rad_s = Vec3::Zero();
  std::optional<CircularOrbit> orbit;
  /// Every camera head (>= 1; one head: label CAMERA, identity mounting, `faults`).
  std::vector<CameraHead> heads = {CameraHead{}};

  /// Throws InputError naming the file, section and key.
  static Scenario load(const std::string& path);
  static Scenario fromConfig(const mrpt::config::CConfigFileBase& cfg, const std::string& source,
                             const std::string& base_dir = ".");

  int frameCount() const;
  double frameTime(int k) const { return k / frame_rate_hz; }
  int gyroSampleCount() const;  ///< samples at t_j = j / rate_hz, j = 1.. while t_j <= duration
  double gyroTime(int j) const { return gyro ? j / gyro->rate_hz : 0.0; }
  /// VELOCITY samples at t_j = j / velocity_rate_hz, j = 0.. while t_j <= duration (the first
  /// at t = 0: the first frame has one); none without an orbit or at rate 0.
  int velocitySampleCount() const;
  double velocityTime(int j) const { return orbit ? j / orbit->velocity_rate_hz : 0.0; }
  /// [km/s] the observer's velocity relative to the Earth's centre (zero without an orbit).
  Vec3 observerVelocity(double t) const { return orbit ? orbit->velocityAt(t) : Vec3::Zero(); }
  double epochJyear() const;
  /// The clock: UTC of time t [s] from the start (exact to the clock tick).
  mrpt::Clock::time_point timestamp(double t) const;
  /// Limits the run to n frames (duration = n / frame rate).
  void limitFrames(int n);
};

/// Builds the in-memory star database a scenario renders from (the catalog of
/// `catalog_path` or the default one, at the scenario's epoch, V <= mag_limit).
std::shared_ptr<const StarDatabase> buildScenarioDatabase(const Scenario& sc);

/// One simulated camera frame.
struct SimFrame {
  int index = 0;
  double t = 0;             ///< [s] from the start, mid-exposure
  double exposure_s = 0;    ///< [s] this frame's exposure (SensorParams::exposureAt)
  double stamp_t = 0;       ///< [s] the camera's clock at t (t unless its clock jumped)
  bool dropped = false;     ///< the camera delivered nothing (image empty)
  Quat q_ib = Quat::Identity();
  Vec3 rate_body = Vec3::Zero();
  cv::Mat image;            ///< CV_8U or CV_16U
  std::vector<TrueStar> truth;
  int spikes = 0;
  int radiation_hits = 0;   ///< particles that crossed the detector (sensors/sim/radiation.hpp)
};

struct GyroSample {
  int index = 0;
  double t = 0;                   ///< [s] from the start: end of the sample interval
  Vec3 rate = Vec3::Zero();       ///< measured mean body rate over the interval [rad/s]
  Vec3 true_bias = Vec3::Zero();  ///< the gyro's true bias after the sample [rad/s]
};

/// The gyro of a scenario: samples at t_j = j / rate_hz (j = 1, 2, ...), each the mean
/// rate over [t_j-1, t_j] measured by GyroSimulator on the scenario's motion, seeded from
/// the run seed. Sequential (the bias random walk).
class GyroStream {
 public:
  GyroStream(const Scenario& sc, uint64_t seed);
  /// False when the scenario has no gyro or the run is over.
  bool next(GyroSample& out);
  /// Time [s] of the next sample (meaningless when next() would return false).
  double nextTime() const;

 private:
  Scenario sc_;
  std::unique_ptr<GyroSimulator> gyro_;
  int next_ = 1;
  uint64_t seed_ = 0;
  Vec3 held_ = Vec3::Zero();  // a stuck axis' last good reading (faults.hpp)
};

/// The VELOCITY samples of a scenario's orbit (Scenario::velocitySampleCount), exact.
struct VelocitySample {
  double t = 0;                      ///< [s] from the start
  Vec3 velocity_km_s = Vec3::Zero();
};
class VelocityStream {
 public:
  explicit VelocityStream(const Scenario& sc) : sc_(sc) {}
  bool next(VelocitySample& out);
  double nextTime() const { return sc_.velocityTime(next_); }
  bool done() const { return next_ >= sc_.velocitySampleCount(); }

 private:
  Scenario sc_;
  int next_ = 0;
};

class SkySimulator {
 public:
  /// Uses the scenario's database / catalog (built here) and seed `seed`; renders camera
  /// head `head` (Scenario::heads; its own noise streams unless it is head 0).
  SkySimulator(const Scenario& sc, uint64_t seed, int head = 0);
  /// Uses a given star source (tests, synthetic skies).
  SkySimulator(const Scenario& sc, uint64_t seed, std::shared_ptr<const StarSource> stars,
               int head = 0);
  const CameraHead& head() const { return head_; }
  mrpt::poses::CPose3D mount() const { return head_.pose(); }
  /// The star source it renders (another head's simulator can share it).
  const std::shared_ptr<const StarSource>& stars() const { return stars_; }

  const Scenario& scenario() const { return sc_; }
  uint64_t seed() const { return seed_; }
  const Detector& detector() const { return detector_; }
  const std::vector<ExtraSource>& falseSources() const { return render_opts_.extras; }

  /// Frame k, deterministic for (scenario, seed, k) whatever was rendered before.
  /// Not thread-safe (one simulator per thread).
  SimFrame frame(int k) const;

  /// The gyro samples in order (see GyroStream).
  bool nextGyro(GyroSample& out) { return gyro_.next(out); }

 private:
  void init();

  Scenario sc_;
  uint64_t seed_;
  CameraHead head_;
  FaultParams faults_;            // the head's camera faults
  Quat q_bc_ = Quat::Identity();  // body from camera
  uint64_t image_seed_;           // the head's noise, clutter and fault streams
  std::shared_ptr<const StarDatabase> db_;
  std::shared_ptr<const StarSource> stars_;
  Detector detector_;
  std::unique_ptr<StarRenderer> renderer_;
  RenderOptions render_opts_;
  cv::Mat background_;
  GyroStream gyro_;
};

}  // namespace st

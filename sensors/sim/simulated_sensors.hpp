/// @file simulated_sensors.hpp
/// The simulated star camera and gyro as MRPT sensors (mrpt::hwdrivers::CGenericSensor), so
/// that rawlog-grabber style apps run on them as if they were hardware. Both play a scenario
/// .ini (scenario.hpp) in real time with the same model as `startracker simulate`: frame k
/// is emitted once the wall clock passes its mid-exposure time plus half the exposure, gyro
/// sample j when it passes t_j, both counted from a start shared by all simulated sensors of
/// the process (the first doProcess() of any of them). Their timestamps are the scenario's
/// clock, Scenario::timestamp(t) (its start_time + t), as `simulate` stamps them: the sky is
/// rendered for that date, so a recording's stamps give replay the epoch of the sky. When the process falls behind by more than one frame, the
/// camera skips the stale frames (as a real camera drops them) and counts them.
///
/// .ini section (besides CGenericSensor's process_rate, sensorLabel, ...):
///   driver = CSimulatedStarCamera | CSimulatedGyro
///   scenario_file = path/to/scenario.ini   (required; relative to the working directory,
///                                           else to the folder of the .ini file)
///   seed = N                                (default: the scenario's seed)
///   truth_label = GROUND_TRUTH              (camera: also emit the truth per frame with this
///                                            label; empty = no truth. Gyro: default empty;
///                                            set, the gyro emits the scenario's attitude at
///                                            its frame times, without stars, for frames that
///                                            come from elsewhere, e.g. a folder rendered
///                                            from the scenario played by a real grabber)
///   scenario_head = 0                       (camera: which of the scenario's camera heads,
///                                            head_sections order, it is: its label's frames
///                                            carry that head's mounting as cameraPose, and
///                                            the truth's stars that head index)
///   velocity_label = VELOCITY               (gyro: the scenario's [orbit] velocity samples,
///                                            the rawlog contract's VELOCITY, at its
///                                            velocity_rate_hz; empty = none)
/// process_rate must be at least the frame rate (camera) or gyro rate (gyro) to keep up.
/// The section is read strictly (simulatedSensorSchema): an unknown key is an error with
/// the nearest valid key, unless the section's driver is another class (CStarTrackerSensor
/// hands its own section to an inner CSimulatedStarCamera and checks its keys itself).
///
/// The factory knows them only after registerSimulatedSensors() (or doRegister()).
#pragma once
#include <mrpt/core/Clock.h>
#include <mrpt/hwdrivers/CGenericSensor.h>

#include <memory>
#include <optional>
#include <string>

#include "config/schema.hpp"
#include "sensors/mrpt/image_source.hpp"

namespace st {

/// The keys of a simulated-sensor section (CGenericSensor's common keys + ours).
struct SimulatedSensorKeys {
  std::string driver;
  double process_rate = 0;
  int max_queue_len = 200, grab_decimation = 1;
  std::string sensorLabel;
  std::string scenario_file;
  std::string seed;  ///< empty = the scenario's seed
  std::string truth_label = "GROUND_TRUTH";  ///< the gyro's default is empty (no truth)
  std::string velocity_label = "VELOCITY";  ///< gyro only: the orbit's velocity samples
  int scenario_head = 0;  ///< camera only: the scenario's camera head it renders
};
/// The schema for CSimulatedStarCamera (`camera`) or CSimulatedGyro.
const SectionSchema<SimulatedSensorKeys>& simulatedSensorSchema(bool camera);
/// Whether `section` configures one of the simulated sensors (its driver names it).
bool isSimulatedSensorSection(const mrpt::config::CConfigFileBase& cfg, const std::string& section);
/// Strict read of such a section; its effective configuration in ini form.
std::string printSimulatedSensorSection(const IniReader& r, const std::string& section);

class SkySimulator;
class GyroStream;
class VelocityStream;
struct Scenario;
struct CameraHead;

class CSimulatedStarCamera : public mrpt::hwdrivers::CGenericSensor, public StarImageSource {
  DEFINE_GENERIC_SENSOR(CSimulatedStarCamera)
 public:
  CSimulatedStarCamera();
  ~CSimulatedStarCamera() override;
  void initialize() override;
  void doProcess() override;
  void setPathForExternalImages(const std::string& directory) override;

  int framesEmitted() const { return emitted_; }
  int framesSkipped() const { return skipped_; }
  bool finished() const override;
  /// The scenario's camera, exposure, detector noise and epoch (StarImageSource).
  ImageSourceFacts facts() const override;

 protected:
  void loadConfig_sensorSpecific(const mrpt::config::CConfigFileBase& cfg,
                                 const std::string& section) override;

 private:
  std::string scenario_file_, truth_label_ = "GROUND_TRUTH";
  std::optional<uint64_t> seed_;
  int head_ = 0;  // the scenario's camera head
  std::string head_key_;  // where scenario_head is written, for its error
  const CameraHead& head(const Scenario& sc) const;
  std::unique_ptr<Scenario> scenario_;
  std::unique_ptr<SkySimulator> sim_;
  int next_frame_ = 0, emitted_ = 0, skipped_ = 0;
};

class CSimulatedGyro : public mrpt::hwdrivers::CGenericSensor, public FiniteSensor {
  DEFINE_GENERIC_SENSOR(CSimulatedGyro)
 public:
  CSimulatedGyro();
  ~CSimulatedGyro() override;
  void initialize() override;
  void doProcess() override;

  int samplesEmitted() const { return emitted_; }
  bool finished() const override { return done_; }

 protected:
  void loadConfig_sensorSpecific(const mrpt::config::CConfigFileBase& cfg,
                                 const std::string& section) override;

 private:
  void appendTruthsUpTo(double t);
  void appendVelocitiesUpTo(double t);

  std::string scenario_file_;
  std::optional<uint64_t> seed_;
  std::unique_ptr<Scenario> scenario_;
  std::unique_ptr<GyroStream> stream_;
  std::string truth_label_;  // empty: no truth
  std::string velocity_label_;
  std::unique_ptr<VelocityStream> velocity_;
  int next_truth_ = 0;       // the next frame time whose truth is due
  int emitted_ = 0;
  bool done_ = false;
};

/// Registers both classes with MRPT's sensor factory (idempotent).
void registerSimulatedSensors();

/// Seconds since the shared start of the simulated sensors (starts the clock on first call),
/// and the wall-clock time of that start (when the sensors emit, not their stamps).
double simulatedSensorsElapsed();
mrpt::Clock::time_point simulatedSensorsStart();
/// Restarts the shared clock at the next call (tests that run several live sessions).
void resetSimulatedSensorsClock();

}  // namespace st

#include "sensors/sim/scenario.hpp"

#include <mrpt/config/CConfigFile.h>

#include <chrono>
#include <cmath>
#include <filesystem>

#include "catalog/star_catalog.hpp"
#include "catalog/star_database.hpp"
#include "common/conventions.hpp"
#include "common/errors.hpp"
#include "common/mrpt_convert.hpp"
#include "sensors/sim/radiation.hpp"
#include "sensors/sim/random_streams.hpp"

namespace st {

Scenario Scenario::load(const std::string& path) {
  if (!std::filesystem::is_regular_file(path))
    throw InputError(path + ": scenario file does not exist");
  const auto file = openIniFile(path);
  const mrpt::config::CConfigFile& cfg = *file;
  const std::string dir = std::filesystem::path(path).parent_path().string();
  return fromConfig(cfg, path, dir.empty() ? "." : dir);
}

int Scenario::frameCount() const {
  // Frames at k / rate while k / rate < duration (a tiny tolerance absorbs rounding).
  return std::max(1, static_cast<int>(std::ceil(duration_s * frame_rate_hz - 1e-9)));
}

int Scenario::gyroSampleCount() const {
  if (!gyro) return 0;
  return static_cast<int>(std::floor(duration_s * gyro->rate_hz + 1e-9));
}

int Scenario::velocitySampleCount() const {
  if (!orbit || !(orbit->velocity_rate_hz > 0)) return 0;
  return 1 + static_cast<int>(std::floor(duration_s * orbit->velocity_rate_hz + 1e-9));
}

bool VelocityStream::next(VelocitySample& out) {
  if (done()) return false;
  out.t = sc_.velocityTime(next_++);
  out.velocity_km_s = sc_.observerVelocity(out.t);
  return true;
}

double Scenario::epochJyear() const { return julianYearFromUnixSeconds(start_unix_s); }

mrpt::Clock::time_point Scenario::timestamp(double t) const {
  return timestampAfter(start_unix_s, t);
}

void Scenario::limitFrames(int n) {
  if (n <= 0) throw InputError("--frames must be > 0, got " + std::to_string(n));
  duration_s = n / frame_rate_hz;
}

std::shared_ptr<const StarDatabase> buildScenarioDatabase(const Scenario& sc) {
  if (!sc.database_path.empty())
    return std::make_shared<const StarDatabase>(StarDatabase::load(sc.database_path));
  const std::string cat_path =
      sc.catalog_path.empty() ? StarDatabase::defaultCatalogPath() : sc.catalog_path;
  DatabaseParams p{};
  p.max_pair_angle = deg2rad(0.05);  // the renderer needs the stars, not the pair table
  p.mag_limit = sc.mag_limit;
  p.epoch_jyear = sc.epochJyear();
  p.aberration = sc.aberration;
  p.double_star_sep = 0;  // render double stars as they are
  p.max_stars_per_region = 0;
  p.neighbour_radius = 0;
  return std::make_shared<const StarDatabase>(StarDatabase::build(loadCatalog(cat_path), p));
}

// ---- SkySimulator ---------------------------------------------------------------------

namespace {

const CameraHead& headOf(const Scenario& sc, int head) {
  if (head < 0 || head >= static_cast<int>(sc.heads.size()))
    throw InputError(sc.source + ": no camera head " + std::to_string(head));
  return sc.heads[static_cast<std::size_t>(head)];
}

/// Head 0 keeps the run seed's streams (a one-head scenario renders what it always did).
uint64_t headSeed(uint64_t seed, int head) {
  return seed + static_cast<uint64_t>(head) * 0x9E3779B97F4A7C15ull;
}

}  // namespace

SkySimulator::SkySimulator(const Scenario& sc, uint64_t seed, int head)
    : sc_(sc),
      seed_(seed),
      head_(headOf(sc, head)),
      faults_(head_.faults.value_or(sc.faults)),
      q_bc_(head_.R_body_cam),
      image_seed_(headSeed(seed, head)),
      db_(buildScenarioDatabase(sc)),
      stars_(std::make_shared<DatabaseStarSource>(*db_)),
      detector_(sc.sensor, sc.camera.width(), sc.camera.height()),
      gyro_(sc, seed) {
  init();
}

SkySimulator::SkySimulator(const Scenario& sc, uint64_t seed,
                           std::shared_ptr<const StarSource> stars, int head)
    : sc_(sc),
      seed_(seed),
      head_(headOf(sc, head)),
      faults_(head_.faults.value_or(sc.faults)),
      q_bc_(head_.R_body_cam),
      image_seed_(headSeed(seed, head)),
      stars_(std::move(stars)),
      detector_(sc.sensor, sc.camera.width(), sc.camera.height()),
      gyro_(sc, seed) {
  init();
}

mrpt::poses::CPose3D CameraHead::pose() const { return mountingPose(mount_ypr_deg); }

void SkySimulator::init() {
  if (!sc_.motion) throw InputError(sc_.source + ": scenario has no motion profile");
  renderer_ = std::make_unique<StarRenderer>(sc_.camera, sc_.sensor, *stars_);
  render_opts_.extras = placeFalseSources(faults_, sc_.camera, *sc_.motion, sc_.duration_s,
                                          sc_.sensor.psf_sigma_px, image_seed_);
  render_opts_.missing_star_fraction = faults_.missing_star_fraction;
  render_opts_.missing_star_seed = image_seed_;
  background_ = detector_.meanBackground();
}

SimFrame SkySimulator::frame(int k) const {
  SimFrame f;
  f.index = k;
  f.t = sc_.frameTime(k);
  f.q_ib = canonical(sc_.motion->attitude(f.t));
  f.rate_body = sc_.motion->rateBody(f.t);
  const FaultParams& faults = faults_;
  f.stamp_t = cameraClock(faults, f.t);
  f.dropped = isFrameDropped(faults, image_seed_, k, f.t);
  const MotionProfile& motion = *sc_.motion;
  const double t_mid = f.t;
  // The head's camera attitude: R_ic = R_ib R_bc.
  const Quat q_bc = q_bc_;
  const AttitudeAt q_at = [&motion, t_mid, q_bc](double tau) {
    return Quat(motion.attitude(t_mid + tau) * q_bc);
  };
  f.exposure_s = sc_.sensor.exposureAt(sc_.camera, q_bc.conjugate() * f.rate_body);
  // Sky and dark current (hot pixels too) grow with the exposure like the starlight.
  cv::Mat electrons = f.exposure_s == sc_.sensor.exposure_s
                          ? background_.clone()
                          : cv::Mat(background_ * (f.exposure_s / sc_.sensor.exposure_s));
  RenderOptions opts = render_opts_;
  opts.exposure_s = f.exposure_s;
  // An exposure is ~0.1 s of a 90-minute orbit: the velocity at mid-exposure is its velocity.
  opts.observer_velocity_km_s = sc_.observerVelocity(f.t);
  f.truth = renderer_->render(q_at, electrons, opts);
  if (f.dropped) return f;
  const int shown = frozenImageSource(faults, k, f.t, sc_.frame_rate_hz);
  if (shown != k) {  // a stuck readout: the earlier image again, the truth of now
    SimFrame old = frame(shown);
    if (!old.image.empty()) {
      f.image = old.image;
      f.spikes = old.spikes;
      f.radiation_hits = old.radiation_hits;
      return f;
    }
  }
  std::mt19937_64 clutter = makeRng(image_seed_, RandomStream::kFrameClutter, static_cast<uint64_t>(k));
  f.spikes = addSpikes(electrons, faults, clutter);
  f.radiation_hits = static_cast<int>(
      addRadiationHits(electrons, sc_.sensor, sc_.sensor.radiation_flux_cm2_s * saaFactor(faults, f.t),
                       f.exposure_s, clutter)
          .size());
  addBlinding(electrons, faults, f.t, f.exposure_s);
  std::mt19937_64 noise = makeRng(image_seed_, RandomStream::kFrameNoise, static_cast<uint64_t>(k));
  f.image = detector_.expose(electrons, noise);
  return f;
}

GyroStream::GyroStream(const Scenario& sc, uint64_t seed) : sc_(sc), seed_(seed) {
  if (sc_.gyro) {
    if (!sc_.motion) throw InputError(sc_.source + ": scenario has no motion profile");
    gyro_ = std::make_unique<GyroSimulator>(*sc_.gyro, streamSeed(seed, RandomStream::kGyro),
                                            sc_.gyro_initial_bias_rad_s);
  }
}

double GyroStream::nextTime() const { return sc_.gyroTime(next_); }

bool GyroStream::next(GyroSample& out) {
  if (!gyro_ || next_ > sc_.gyroSampleCount()) return false;
  const int j = next_++;
  out.index = j;
  out.t = sc_.gyroTime(j);
  out.rate = gyro_->sample(*sc_.motion, sc_.gyroTime(j - 1), out.t);
  out.true_bias = gyro_->bias();
  applyGyroFaults(out.rate, held_, sc_.faults, seed_, j, out.t, sc_.gyro->rate_hz);
  return true;
}

}  // namespace st

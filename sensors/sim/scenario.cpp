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

SkySimulator::SkySimulator(const Scenario& sc, uint64_t seed)
    : sc_(sc),
      seed_(seed),
      db_(buildScenarioDatabase(sc)),
      stars_(std::make_shared<DatabaseStarSource>(*db_)),
      detector_(sc.sensor, sc.camera.width(), sc.camera.height()),
      gyro_(sc, seed) {
  init();
}

SkySimulator::SkySimulator(const Scenario& sc, uint64_t seed,
                           std::shared_ptr<const StarSource> stars)
    : sc_(sc),
      seed_(seed),
      stars_(std::move(stars)),
      detector_(sc.sensor, sc.camera.width(), sc.camera.height()),
      gyro_(sc, seed) {
  init();
}

void SkySimulator::init() {
  if (!sc_.motion) throw InputError(sc_.source + ": scenario has no motion profile");
  renderer_ = std::make_unique<StarRenderer>(sc_.camera, sc_.sensor, *stars_);
  render_opts_.extras = placeFalseSources(sc_.faults, sc_.camera, *sc_.motion, sc_.duration_s,
                                          sc_.sensor.psf_sigma_px, seed_);
  render_opts_.missing_star_fraction = sc_.faults.missing_star_fraction;
  render_opts_.missing_star_seed = seed_;
  background_ = detector_.meanBackground();
}

SimFrame SkySimulator::frame(int k) const {
  SimFrame f;
  f.index = k;
  f.t = sc_.frameTime(k);
  f.q_ib = canonical(sc_.motion->attitude(f.t));
  f.rate_body = sc_.motion->rateBody(f.t);
  f.stamp_t = cameraClock(sc_.faults, f.t);
  f.dropped = isFrameDropped(sc_.faults, seed_, k, f.t);
  const MotionProfile& motion = *sc_.motion;
  const double t_mid = f.t;
  const AttitudeAt q_at = [&motion, t_mid](double tau) { return motion.attitude(t_mid + tau); };
  f.exposure_s = sc_.sensor.exposureAt(sc_.camera, f.rate_body);
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
  const int shown = frozenImageSource(sc_.faults, k, f.t, sc_.frame_rate_hz);
  if (shown != k) {  // a stuck readout: the earlier image again, the truth of now
    SimFrame old = frame(shown);
    if (!old.image.empty()) {
      f.image = old.image;
      f.spikes = old.spikes;
      return f;
    }
  }
  std::mt19937_64 clutter = makeRng(seed_, RandomStream::kFrameClutter, static_cast<uint64_t>(k));
  f.spikes = addSpikes(electrons, sc_.faults, clutter);
  addBlinding(electrons, sc_.faults, f.t, f.exposure_s);
  std::mt19937_64 noise = makeRng(seed_, RandomStream::kFrameNoise, static_cast<uint64_t>(k));
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

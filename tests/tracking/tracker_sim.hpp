// Simulated star-tracker frames for the tracker tests and benchmark: the committed Hipparcos
// subset as database, a 16 x 12 deg camera, the SIM helper's renderer (PSF, blur) and
// detector (shot, dark, read noise, 12-bit ADC).
#pragma once
#include <mrpt/core/Clock.h>

#include <memory>
#include <random>
#include <vector>

#include <opencv2/core.hpp>

#include "catalog/star_catalog.hpp"
#include "catalog/star_database.hpp"
#include "common/conventions.hpp"
#include "sensors/camera/camera_model.hpp"
#include "sensors/tracking/tracker_options.hpp"
#include "sensors/sim/detector.hpp"
#include "sensors/sim/motion.hpp"
#include "sensors/sim/sensor_params.hpp"
#include "sensors/sim/star_renderer.hpp"
#include "sensors/sim/star_source.hpp"

namespace st::test {

/// Database epoch and the frames' start time (the same instant: no epoch mismatch).
constexpr double kSimEpochJyear = 2020.0;
inline mrpt::Clock::time_point simTime(double t_s) {
  return mrpt::Clock::fromDouble(unixSecondsFromJulianYear(kSimEpochJyear) + t_s);
}

inline const CameraModel& simCamera() {
  static const CameraModel cam = CameraModel::fromFov(800, 600, deg2rad(16.0));
  return cam;
}

inline const StarDatabase& simDatabase() {
  static const StarDatabase db = [] {
    const StarCatalog cat = loadHipparcos(StarDatabase::defaultCatalogPath());
    DatabaseParams p{};
    p.max_pair_angle = simCamera().halfDiagonalFov() * 2.0 + deg2rad(0.5);
    p.mag_limit = 6.5;
    p.epoch_jyear = kSimEpochJyear;
    p.aberration = true;
    p.double_star_sep = arcsec2rad(10.0);
    p.max_stars_per_region = 0;
    p.neighbour_radius = deg2rad(5.0);
    return StarDatabase::build(cat, p);
  }();
  return db;
}

inline SensorParams simSensor() {
  SensorParams s;
  s.bit_depth = 12;
  s.exposure_s = 0.1;
  s.psf_sigma_px = 1.0;
  s.aperture_diameter_m = 0.03;
  return s;
}

/// Tracker options matching simSensor(): the detector's noise model must know the ADC gain
/// (shot-noise variance S / gain) and the read noise, or the centroid covariances are off by
/// the gain ratio.
inline TrackerOptions simTrackerOptions() {
  const SensorParams s = simSensor();
  TrackerOptions o;
  o.exposure_s = s.exposure_s;
  o.detect.gain_e_per_adu = s.gain();
  o.detect.read_noise_adu = s.read_noise_e / s.gain();
  return o;
}

/// Renders noisy frames of the database's stars for a motion profile.
class FrameSimulator {
 public:
  /// `camera` is the true camera the frames are rendered through (a tracker may be given
  /// another: an imperfect camera file).
  explicit FrameSimulator(uint64_t seed, const CameraModel& camera = simCamera())
      : camera_(camera),
        source_(simDatabase()),
        sensor_(simSensor()),
        renderer_(camera_, sensor_, source_),
        detector_(sensor_, camera_.width(), camera_.height()),
        rng_(seed) {}

  struct Frame {
    cv::Mat image;
    Quat q_ib;                    ///< truth at mid-exposure
    Vec3 rate_body;               ///< truth
    std::vector<TrueStar> stars;  ///< truth: rendered catalog stars in the image
    double t_s = 0;               ///< [s] from the start of the run (the tracker's time)
    mrpt::Clock::time_point t;    ///< the same instant as an MRPT timestamp
  };

  Frame frame(const MotionProfile& motion, double t_s) {
    Frame f;
    f.q_ib = motion.attitude(t_s);
    f.rate_body = motion.rateBody(t_s);
    f.t_s = t_s;
    f.t = simTime(t_s);
    cv::Mat e = detector_.meanBackground().clone();
    f.stars = renderer_.render([&](double tau) { return motion.attitude(t_s + tau); }, e);
    f.image = detector_.expose(e, rng_);
    return f;
  }

  /// A frame with no stars (lens cap, Sun blinding): background and noise only.
  Frame darkFrame(double t_s) {
    Frame f;
    f.t_s = t_s;
    f.t = simTime(t_s);
    f.image = detector_.expose(detector_.meanBackground(), rng_);
    return f;
  }

  const SensorParams& sensor() const { return sensor_; }

 private:
  CameraModel camera_;
  DatabaseStarSource source_;
  SensorParams sensor_;
  StarRenderer renderer_;
  Detector detector_;
  std::mt19937_64 rng_;
};

}  // namespace st::test

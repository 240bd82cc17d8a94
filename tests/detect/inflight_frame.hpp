/// @file inflight_frame.hpp
/// Test helper: frames of an in-flight star camera like the Swarm heads (issue 34): 752x290
/// px, rows binned 2x (fy = fx / 2, 18.4 deg wide), 8-bit with the bright stars clipped, a low
/// flat background, and radiation hits from a particle flux (sensors/sim/radiation.hpp),
/// rendered by the simulator from the real catalog.
#pragma once
#include <memory>
#include <random>
#include <vector>

#include <opencv2/core.hpp>

#include "catalog/database_cache.hpp"
#include "catalog/database_recipe.hpp"
#include "common/conventions.hpp"
#include "sensors/sim/detector.hpp"
#include "sensors/sim/radiation.hpp"
#include "sensors/sim/star_renderer.hpp"
#include "sensors/sim/star_source.hpp"

namespace st::test {

/// The Swarm heads' nominal geometry.
inline CameraModel inflightCamera() { return CameraModel(752, 290, 2317.6, 1158.8, 375.5, 144.5); }

/// 8-bit, gain 10 e-/ADU (a V 5.5 star peaks at ~20 ADU, V 3 clips), read noise 15 e-, PSF
/// sigma 1 native px (0.5 px along the binned rows); hits of 80 e-/um over 15 um (~120 ADU,
/// lognormal spread 0.7: many above the faint stars, a few clipped like the bright ones).
inline SensorParams inflightSensor() {
  SensorParams s;
  s.aperture_diameter_m = 0.02;
  s.exposure_s = 0.1;
  s.psf_sigma_px = 1.0;
  s.binning_y = 2;
  s.bit_depth = 8;
  s.gain_e_per_adu = 10;
  s.read_noise_e = 15;
  s.full_well_e = 20000;
  s.bias_adu = 12;
  s.sky_e_px_s = 5;
  s.dark_current_e_px_s = 20;
  s.pixel_pitch_um = 10;
  s.radiation_depth_um = 15;
  s.radiation_e_per_um = 80;
  s.radiation_energy_spread = 0.7;
  return s;
}

/// The database `solve --camera` builds for that camera (epoch 2014.8, as the Swarm frames).
inline std::shared_ptr<const StarDatabase> inflightDatabase() {
  const CameraModel cam = inflightCamera();
  CameraDatabaseRecipe r;
  r.diagonal_fov_rad = 2 * cam.halfDiagonalFov();
  r.pixel_scale_rad = cam.pixelScale();
  r.mag_limit = 6.6;
  r.epoch_jyear = 2014.8;
  r.aberration = true;
  return cameraDatabase(r);
}

struct InflightFrame {
  cv::Mat image;  ///< CV_8U
  Quat q_ib;      ///< the truth (body = camera)
  std::vector<TrueStar> truth;
  std::vector<RadiationHit> hits;
};

/// Renders the sky at a random attitude (from `seed`) with on average `mean_hits` hits (a
/// Poisson count from the flux that gives that mean).
class InflightSimulator {
 public:
  explicit InflightSimulator(const StarDatabase& db)
      : source_(db), sensor_(inflightSensor()), cam_(inflightCamera()),
        renderer_(cam_, sensor_, source_), detector_(sensor_, cam_.width(), cam_.height()) {}

  const SensorParams& sensor() const { return sensor_; }

  /// [cm^2] the detector's area (native pixels x pitch).
  double areaCm2() const {
    return cam_.width() * sensor_.binning_x * sensor_.pixel_pitch_um * 1e-4 * cam_.height() *
           sensor_.binning_y * sensor_.pixel_pitch_um * 1e-4;
  }

  InflightFrame frame(uint64_t seed, double mean_hits) const {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0, 1);
    InflightFrame f;
    f.q_ib = attitudeFromRaDecRoll({kTwoPi * u(rng), std::asin(2 * u(rng) - 1), kTwoPi * u(rng)});
    cv::Mat e = detector_.meanBackground().clone();
    f.truth = renderer_.render([&](double) { return f.q_ib; }, e);
    const double flux = mean_hits / (areaCm2() * sensor_.exposure_s);
    f.hits = addRadiationHits(e, sensor_, flux, sensor_.exposure_s, rng);
    f.image = detector_.expose(e, rng);
    return f;
  }

 private:
  DatabaseStarSource source_;
  SensorParams sensor_;
  CameraModel cam_;
  StarRenderer renderer_;
  Detector detector_;
};

}  // namespace st::test

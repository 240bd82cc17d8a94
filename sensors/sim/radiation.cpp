#include "sensors/sim/radiation.hpp"

#include <algorithm>
#include <cmath>

#include "common/conventions.hpp"
#include "sensors/sim/psf.hpp"

namespace st {
namespace {
// [native px] sigma of the charge's spread by diffusion before it is collected.
constexpr double kDiffusionPx = 0.3;
// Steps along a track per image pixel: the charge lies as a continuous line.
constexpr double kStepsPerPx = 4;
}  // namespace

void renderRadiationHit(cv::Mat& electrons, const SensorParams& p, const RadiationHit& hit) {
  const double len = (hit.to - hit.from).norm();
  const int steps = std::max(1, static_cast<int>(std::ceil(len * kStepsPerPx)));
  const double sx = kDiffusionPx / p.binning_x, sy = kDiffusionPx / p.binning_y;
  for (int k = 0; k < steps; ++k) {
    const double s = steps == 1 ? 0.5 : static_cast<double>(k) / (steps - 1);
    addGaussianStarXY(electrons, hit.from + s * (hit.to - hit.from), hit.electrons / steps, sx, sy);
  }
}

std::vector<RadiationHit> addRadiationHits(cv::Mat& electrons, const SensorParams& p,
                                           double flux_cm2_s, double exposure_s,
                                           std::mt19937_64& rng) {
  std::vector<RadiationHit> hits;
  if (!(flux_cm2_s > 0) || !(exposure_s > 0)) return hits;
  CV_Assert(electrons.type() == CV_64FC1);
  const double um2cm = 1e-4;
  const double area_cm2 = electrons.cols * p.binning_x * p.pixel_pitch_um * um2cm *
                          electrons.rows * p.binning_y * p.pixel_pitch_um * um2cm;
  const int n = std::poisson_distribution<int>(flux_cm2_s * area_cm2 * exposure_s)(rng);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  std::normal_distribution<double> gauss(0.0, 1.0);
  const double spread = p.radiation_energy_spread;
  hits.reserve(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    RadiationHit h;
    h.from = Vec2(u01(rng) * electrons.cols - 0.5, u01(rng) * electrons.rows - 0.5);
    // Isotropic over the hemisphere through a flat layer: cos^2(theta) uniform; a grazing
    // track is capped at the image's size.
    const double cos_t = std::max(std::sqrt(u01(rng)), 1e-3);
    const double phi = kTwoPi * u01(rng);
    const double lateral_px = p.radiation_depth_um * std::sqrt(1 - cos_t * cos_t) / cos_t /
                              p.pixel_pitch_um;
    h.to = h.from + Vec2(lateral_px * std::cos(phi) / p.binning_x,
                         lateral_px * std::sin(phi) / p.binning_y);
    // Lognormal with mean 1: exp(sigma z - sigma^2 / 2).
    const double factor = std::exp(spread * gauss(rng) - 0.5 * spread * spread);
    h.electrons = p.radiation_e_per_um * p.radiation_depth_um / cos_t * factor;
    renderRadiationHit(electrons, p, h);
    hits.push_back(h);
  }
  return hits;
}

}  // namespace st

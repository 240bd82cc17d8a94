/// @file radiation.hpp
/// Radiation hits on the simulated detector (issue 34): charged particles (trapped protons,
/// electrons, cosmic rays) cross the silicon during the exposure and leave charge along their
/// path; no optics stand between, so a hit is as sharp as the pixels: a dot of 1-3 px, or a
/// short track at a random angle.
///   - count per frame: Poisson, mean flux [cm^-2 s^-1] x detector area x exposure;
///   - direction: isotropic over the hemisphere facing the detector, so through a flat
///     layer the zenith angle theta has cos^2(theta) uniform (a cos-weighted flux);
///   - the path across the image: depth x tan(theta) in the azimuth phi, in native pixels
///     (binned pixels shorten it along the binned axis);
///   - charge: e_per_um x depth / cos(theta) x a lognormal factor (mean 1, sigma the energy
///     spread), shared evenly along the track with a small charge diffusion (0.3 native px).
/// A South Atlantic Anomaly pass (or a solar storm) multiplies the flux during an interval
/// ([faults] saa_start_s, saa_end_s, saa_flux_factor).
#pragma once
#include <random>
#include <vector>

#include <opencv2/core.hpp>

#include "common/attitude.hpp"
#include "sensors/sim/sensor_params.hpp"

namespace st {

/// One hit as simulated (ground truth for tests): where its track starts and ends [image px]
/// and its charge [e-].
struct RadiationHit {
  Vec2 from = Vec2::Zero(), to = Vec2::Zero();
  double electrons = 0;
};

/// Adds the hits of one exposure of `exposure_s` [s] at flux `flux_cm2_s` to a mean-electron
/// image (CV_64F) and returns them. Draws nothing from `rng` when the flux is 0 (scenarios
/// without radiation keep their random streams).
std::vector<RadiationHit> addRadiationHits(cv::Mat& electrons, const SensorParams& p,
                                           double flux_cm2_s, double exposure_s,
                                           std::mt19937_64& rng);

/// Adds `hit` (its track and charge) to a mean-electron image: what addRadiationHits does
/// with each of the hits it draws.
void renderRadiationHit(cv::Mat& electrons, const SensorParams& p, const RadiationHit& hit);

}  // namespace st

/// @file display_image.hpp
/// Images of the near-field display: the star field a screen must show (sky stars placed
/// where a direction from the centre of rotation meets the screen, eq. 57/58 backwards), and
/// a simulated camera photograph of such a screen image at a platform attitude (for trying
/// the solver without a bench, and for the draw -> solve round trip test).
#pragma once
#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

#include "sensors/camera/camera_model.hpp"
#include "sensors/testbed/display_geometry.hpp"

namespace st::testbed {

struct DisplayStar {
  uint32_t id = 0;      ///< catalog id (or the pattern's index)
  Vec2 screen_px;       ///< where it is drawn
  double mag = 0;       ///< V magnitude: sets the dot's brightness
  Vec3 u_sky = Vec3::UnitZ();  ///< the star's direction in the sky frame (ICRS)
};

/// Sky stars (unit vectors u in the sky frame, magnitudes) on the screen when the testbed
/// frame I has attitude q_sky_I in the sky (v_I = R(q_sky_I)^T u): the screen point is where
/// the direction v_I from the centre of rotation meets the plane z = h, so that its database
/// vector (eq. 58) is v_I exactly. Stars off the screen or beyond `max_stars` (faintest
/// dropped) are left out; brightest first.
std::vector<DisplayStar> skyOnDisplay(const DisplayGeometry& g, const std::vector<Vec3>& u_sky,
                                      const std::vector<double>& mag,
                                      const std::vector<uint32_t>& id, const Quat& q_sky_I,
                                      std::size_t max_stars);

struct DrawOptions {
  double dot_sigma_px = 3.0;  ///< Gaussian dot 1-sigma [screen px]: a few camera pixels wide
  double min_peak = 80;       ///< the faintest star's peak (8-bit); the brightest is 255
};
/// The screen image (8-bit, screen_width_px x screen_height_px, black sky): one Gaussian dot
/// per star, peak 255 * 10^(-0.4 (mag - brightest)) floored at min_peak.
cv::Mat drawDisplay(const DisplayGeometry& g, const std::vector<DisplayStar>& stars,
                    const DrawOptions& o = {});

/// What the camera sees at platform attitude q_ib: each camera pixel's ray meets the screen
/// (eq. 56) and takes the screen image's value there (bilinear), scaled by `gain`, on a
/// background `background` with Gaussian read noise `noise_adu` (seeded). 8-bit.
cv::Mat photographDisplay(const cv::Mat& screen, const DisplayGeometry& g, const CameraModel& cam,
                          const Quat& q_ib, double noise_adu, uint64_t seed,
                          double background = 10.0, double gain = 0.9);

}  // namespace st::testbed

#include "sensors/tracking/tracker_options.hpp"

#include "sensors/identify/star_observation.hpp"

#include <cmath>

#include "common/errors.hpp"
#include "sensors/attitude/wahba.hpp"

namespace st {

namespace {

/// The first unusable numeric option: its name and why, or nullptr.
const char* badNumber(const TrackerOptions& o, const char** why) {
  struct Rule {
    bool ok;
    const char* name;
    const char* why;
  };
  const double det = o.R_body_cam.determinant();
  const bool rotation = std::abs(det - 1.0) < 1e-9 &&
                        (o.R_body_cam.transpose() * o.R_body_cam - Mat3::Identity())
                                .cwiseAbs()
                                .maxCoeff() < 1e-9;
  const Rule rules[] = {
      {rotation, "R_body_cam", "must be a rotation matrix"},
      {o.exposure_s >= 0, "exposure_s", "must be >= 0"},
      {o.max_tracked_stars >= 3, "max_tracked_stars", "must be >= 3"},
      {o.min_tracked_stars >= 3, "min_tracked_stars", "must be >= 3 (a check needs > 2 stars)"},
      {o.gate_sigma > 0, "gate_sigma", "must be > 0"},
      {o.blend_separation_px >= 0, "blend_separation_px", "must be >= 0"},
      {o.screen_pull_sigma >= 0, "screen_pull_sigma", "must be >= 0"},
      {o.loss_probability > 0 && o.loss_probability < 0.5, "loss_probability", "in (0, 0.5)"},
      {o.consistency_probability > 0 && o.consistency_probability < 0.5,
       "consistency_probability", "in (0, 0.5)"},
      {o.max_failed_frames >= 1, "max_failed_frames", "must be >= 1"},
      {o.reacquire_budget_s >= 0 && o.reacquire_budget_s <= 3600, "reacquire_budget_s",
       "must be in [0, 3600] s (0 = no limit)"},
      {o.max_propagation_s > 0, "max_propagation_s", "must be > 0"},
      {o.accel_sigma >= 0, "accel_sigma", "must be >= 0"},
      {o.gyro_sigma >= 0, "gyro_sigma", "must be >= 0"},
      {o.min_sigma_px > 0 && o.min_sigma_px <= kMaxCentroidSigmaFloorPx, "min_sigma_px",
       "must be in (0, 2] px"},
      {o.tracking_min_sigma_px > 0 && o.tracking_min_sigma_px <= kMaxCentroidSigmaFloorPx,
       "tracking_min_sigma_px", "must be in (0, 2] px"},
      {o.camera_heal_range >= 0 && o.camera_heal_range <= 0.2, "cam_heal_range",
       "must be in [0, 0.2] (a camera file more than 20 % off is not a camera file)"},
      {o.online_camera.frames_per_fit >= 1, "cam_online_frames", "must be >= 1"},
      {o.online_camera.forgetting > 0 && o.online_camera.forgetting <= 1,
       "cam_forgetting", "must be in (0, 1]"},
      {o.online_camera.prior_focal_rel > 0, "cam_prior_focal_rel", "must be > 0"},
      {o.online_camera.prior_k1 > 0, "cam_prior_k1", "must be > 0"},
      {o.online_camera.max_model_error_px >= 0, "cam_max_model_error_px",
       "must be >= 0"},
  };
  for (const Rule& r : rules) {
    if (!r.ok) {
      *why = r.why;
      return r.name;
    }
  }
  return nullptr;
}

}  // namespace

bool TrackerOptions::isValid(std::string* why) const {
  auto fail = [&](const std::string& name, const std::string& what) {
    if (why) *why = "option '" + name + "': " + what;
    return false;
  };
  const char* reason = nullptr;
  if (const char* name = badNumber(*this, &reason)) return fail(name, reason);
  std::string err;
  if (!detect.isValid(&err)) return fail("detect", err);
  if (!StarIdentifier::create(lis_algorithm, identify, &err)) return fail("lis_algorithm", err);
  if (!WahbaSolver::create(solver, &err)) return fail("solver", err);
  if (!WahbaSolver::create(identify.solver, &err)) return fail("identify.solver", err);
  return true;
}

void TrackerOptions::validate() const {
  std::string why;
  if (!isValid(&why)) throw InputError("star tracker " + why);
}

}  // namespace st

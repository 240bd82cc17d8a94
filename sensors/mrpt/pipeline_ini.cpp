#include "sensors/mrpt/pipeline_ini.hpp"

#include "common/errors.hpp"
#include "sensors/attitude/wahba.hpp"
#include "sensors/identify/identifier.hpp"

namespace st {

const std::set<std::string>& pipelineIniKeys() {
  static const std::set<std::string> keys = {
      "sensor_label", "lis_algorithm", "solver", "identify_solver", "exposure_s",
      "min_sigma_px", "tracking_min_sigma_px", "max_tracked_stars", "min_tracked_stars",
      "drop_saturated", "gate_sigma", "edge_margin_px", "blend_separation_px",
      "loss_probability", "consistency_probability", "max_failed_frames", "frame_to_frame",
      "max_propagation_s", "accel_sigma", "gyro_sigma", "gain_e_per_adu", "read_noise_adu",
      "threshold_sigma", "centroider", "psf_sigma_px", "reject_spikes", "max_stars",
      "identify_max_stars", "pair_sigma"};
  return keys;
}

void readTrackerOptions(const IniReader& r, const std::string& sec, TrackerOptions& o) {
  o.exposure_s = r.num(sec, "exposure_s", o.exposure_s);
  // lost-in-space
  o.lis_algorithm = r.str(sec, "lis_algorithm", o.lis_algorithm);
  o.min_sigma_px = r.num(sec, "min_sigma_px", o.min_sigma_px);
  o.identify.max_stars = r.integer(sec, "identify_max_stars", o.identify.max_stars);
  o.identify.pair_sigma = r.num(sec, "pair_sigma", o.identify.pair_sigma);
  // tracking
  if (r.has(sec, "solver")) o.solver = o.identify.solver = r.str(sec, "solver", o.solver);
  o.identify.solver = r.str(sec, "identify_solver", o.identify.solver);
  o.tracking_min_sigma_px = r.num(sec, "tracking_min_sigma_px", o.tracking_min_sigma_px);
  o.max_tracked_stars = r.integer(sec, "max_tracked_stars", o.max_tracked_stars);
  o.min_tracked_stars = r.integer(sec, "min_tracked_stars", o.min_tracked_stars);
  o.drop_saturated = r.boolean(sec, "drop_saturated", o.drop_saturated);
  o.gate_sigma = r.num(sec, "gate_sigma", o.gate_sigma);
  o.edge_margin_px = r.num(sec, "edge_margin_px", o.edge_margin_px);
  o.blend_separation_px = r.num(sec, "blend_separation_px", o.blend_separation_px);
  o.loss_probability = r.num(sec, "loss_probability", o.loss_probability);
  o.consistency_probability = r.num(sec, "consistency_probability", o.consistency_probability);
  o.max_failed_frames = r.integer(sec, "max_failed_frames", o.max_failed_frames);
  // frame-to-frame prediction
  o.frame_to_frame = r.boolean(sec, "frame_to_frame", o.frame_to_frame);
  o.max_propagation_s = r.num(sec, "max_propagation_s", o.max_propagation_s);
  o.accel_sigma = r.num(sec, "accel_sigma", o.accel_sigma);
  o.gyro_sigma = r.num(sec, "gyro_sigma", o.gyro_sigma);
  // detection
  DetectorOptions& d = o.detect;
  d.gain_e_per_adu = r.num(sec, "gain_e_per_adu", d.gain_e_per_adu);
  d.read_noise_adu = r.num(sec, "read_noise_adu", d.read_noise_adu);
  d.threshold_sigma = r.num(sec, "threshold_sigma", d.threshold_sigma);
  d.centroider = r.str(sec, "centroider", d.centroider);
  d.psf_sigma_px = r.num(sec, "psf_sigma_px", d.psf_sigma_px);
  d.reject_spikes = r.boolean(sec, "reject_spikes", d.reject_spikes);
  d.max_stars = r.integer(sec, "max_stars", d.max_stars);

  // The name checks first: they name their own key.
  std::string err;
  // The solvers first: StarIdentifier::create validates o.identify (its solver included),
  // and a bad identify_solver must be reported under its own key.
  if (!WahbaSolver::create(o.solver, &err))
    throw InputError(r.where(sec, "solver") + " = '" + o.solver + "': " + err);
  if (!WahbaSolver::create(o.identify.solver, &err)) {
    throw InputError(r.where(sec, "identify_solver") + " = '" + o.identify.solver + "': " +
                     err);
  }
  if (!o.isValid(&err)) throw InputError(r.where(sec) + ": star tracker " + err);
}

void readPipelineOptions(const IniReader& r, const std::string& sec, PipelineOptions& o) {
  o.sensor_label = r.str(sec, "sensor_label", o.sensor_label);
  readTrackerOptions(r, sec, o.tracker);
}

}  // namespace st

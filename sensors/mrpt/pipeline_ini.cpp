#include "sensors/mrpt/pipeline_ini.hpp"

#include <cctype>
#include <utility>
#include <vector>

#include "common/errors.hpp"
#include "sensors/attitude/wahba.hpp"
#include "sensors/detect/centroider.hpp"
#include "sensors/detect/dark_frame.hpp"
#include "sensors/identify/identifier.hpp"

namespace st {

/// detect_dark_file: the path, and the dark read from it as the key is read.
template <>
struct IniCodec<DarkFrameFile> {
  static bool present(const IniReader& r, const std::string& s, const std::string& k) {
    return r.has(s, k);
  }
  static void read(const IniReader& r, const std::string& s, const std::string& k,
                   DarkFrameFile& v) {
    v.path = r.str(s, k, "");
    v.image.release();
    if (v.path.empty()) return;
    try {
      v.image = readDarkFrame(v.path);
    } catch (const InputError& e) {
      throw InputError(r.whereKey(s, k) + ": " + e.what());
    }
  }
  static std::string write(const DarkFrameFile& v) { return v.path; }
};

namespace {

const SectionSchema<DetectorOptions>& detectorSchema() {
  using D = DetectorOptions;
  static const auto s =
      SectionSchema<D>()
          .add("gain_e_per_adu", &D::gain_e_per_adu, "[e-/ADU] signal to shot-noise variance")
          .add("read_noise_adu", &D::read_noise_adu, "[ADU] floor of the measured background sigma")
          .add("detect_saturation_adu", &D::saturation_adu,
               "[ADU] saturated from here; 0 = type max")
          .add("detect_threshold_sigma", &D::threshold_sigma,
               "candidate above background + k sigma")
          .renamed("threshold_sigma", "detect_threshold_sigma")
          .add("detect_threshold_mode", &D::threshold_mode,
               "fixed | dynamic: k follows the star count of recent frames (seed 004 8.2.3)")
          .add("detect_dynamic_target_stars", &D::dynamic_target_stars,
               "dynamic: fewer stars lower k; more than twice as many blobs raise it")
          .add("detect_dynamic_min_sigma", &D::dynamic_min_sigma, "dynamic: lowest k")
          .add("detect_dynamic_max_sigma", &D::dynamic_max_sigma, "dynamic: highest k")
          .add("detect_dynamic_step_sigma", &D::dynamic_step_sigma, "dynamic: change of k per frame")
          .add("detect_background_tile_px", &D::background_tile_px,
               "[px] tile of the background median; 0 = one global value")
          .add("detect_dark_file", &D::dark_file,
               "master dark (`startracker dark`: FITS, PNG, TIFF), subtracted first; "
               "empty = none")
          .add("detect_background_samples", &D::background_samples, "pixels sampled per tile")
          .add("detect_prefilter", &D::prefilter, "none | neighbourhood | grid (low thresholds)")
          .add("detect_prefilter_min_count", &D::prefilter_min_count, "of the 25 pixels of 5x5")
          .add("detect_min_area", &D::min_area, "[px] smaller blobs are noise")
          .add("detect_max_area", &D::max_area, "[px] larger blobs are Moon, planets, glare")
          .add("detect_max_stars", &D::max_stars, "brightest detections kept")
          .renamed("max_stars", "detect_max_stars")
          .add("detect_min_separation_px", &D::min_separation_px,
               "[px] closer to a brighter centroid: the same star")
          .add("detect_max_elongation", &D::max_elongation, "above: flagged elongated")
          .add("detect_hot_pixel_fraction", &D::hot_pixel_fraction,
               "peak / 3x3 flux above: hot pixel")
          .add("detect_max_psf_sigma_px", &D::max_psf_sigma_px,
               "[px] wider across its narrow axis: flagged extended (foreground, glow)")
          .add("detect_reject_flags", &D::reject_flags,
               "flags that remove a star: sum of 1 saturated, 2 edge, 4 elongated, 8 hot pixel, "
               "16 extended")
          .choice("centroider", &D::centroider, Centroider::names(), "centroid estimator")
          .add("psf_sigma_px", &D::psf_sigma_px, "[px] PSF sigma; 0 = estimate per star")
          .add("detect_window_margin_px", &D::window_margin_px, "[px] around a blob's box")
          .add("detect_reject_spikes", &D::reject_spikes, "gauss: drop single-pixel spikes, refit")
          .renamed("reject_spikes", "detect_reject_spikes")
          .add("detect_window_sigmas", &D::window_sigmas, "predictive window half-size in sigma")
          .add("detect_max_window_half_px", &D::max_window_half_px, "[px] cap of that half-size");
  return s;
}

const SectionSchema<VerifyOptions>& verifySchema() {
  using V = VerifyOptions;
  static const auto s =
      SectionSchema<V>()
          .add("verify_gate_sigma", &V::gate_sigma, "match gate in combined 1-sigma")
          .add("verify_min_gate_px", &V::min_gate_px, "[px] lower bound of the gate radius")
          .add("verify_false_match_threshold", &V::false_match_threshold,
               "accept below this false-match probability")
          .add("verify_min_matches", &V::min_matches, "fewer matched stars: rejected")
          .add("verify_refine_iterations", &V::refine_iterations, "match / re-solve rounds")
          .add("verify_edge_margin_px", &V::edge_margin_px,
               "[px] predicted stars this close to the border ignored")
          .add("verify_residual_test", &V::residual_test,
               "chi-square test of residuals, outlier removal")
          .add("verify_near_miss_test", &V::near_miss_test, "reject partial matches")
          .add("verify_residual_alpha", &V::residual_alpha,
               "false-alarm probability of either test")
          .add("verify_near_miss_factor", &V::near_miss_factor, "near-miss radius in gate radii")
          .add("verify_max_outlier_fraction", &V::max_outlier_fraction,
               "more outliers removed than this fraction: rejected");
  return s;
}

const SectionSchema<IdentifyOptions>& identifySchema() {
  using I = IdentifyOptions;
  static const auto s =
      SectionSchema<I>()
          .choice("lis_solver", &I::solver, WahbaSolver::names(), "Wahba solver of lost-in-space")
          .renamed("identify_solver", "lis_solver")
          .add("lis_pair_sigma", &I::pair_sigma, "star-pair tolerance in sigma of the angle")
          .renamed("pair_sigma", "lis_pair_sigma")
          .add("lis_scale_tolerance", &I::scale_tolerance, "relative focal-length uncertainty")
          .add("lis_max_stars", &I::max_stars, "brightest observations forming patterns")
          .renamed("identify_max_stars", "lis_max_stars")
          .add("lis_max_stars_retry", &I::max_stars_retry, "one more search over this many")
          .add("lis_max_verifications", &I::max_verifications, "hypotheses verified at most")
          .add("lis_max_candidates", &I::max_candidates, "pattern candidates examined at most")
          .add("lis_magnitude_sigma", &I::magnitude_sigma,
               "[mag] > 0: 2-3 star fields solve by the magnitude tie-break, this the 1-sigma of "
               "a star's magnitude (solve's photometry scatter_mag); 0 = off")
          .include(verifySchema(), &I::verify);
  return s;
}

const SectionSchema<OnlineCameraOptions>& onlineCameraSchema() {
  using O = OnlineCameraOptions;
  static const auto s =
      SectionSchema<O>()
          .add("cam_online", &O::enabled,
               "refine the camera online from verified frames (focal length, k1)")
          .add("cam_online_frames", &O::frames_per_fit,
               "verified frames per online camera fit (fits then come ever more rarely, up to "
               "64x, while they find no model error)")
          .add("cam_forgetting", &O::forgetting,
               "information kept from one online camera fit to the next, (0, 1]")
          .add("cam_prior_focal_rel", &O::prior_focal_rel,
               "1-sigma relative focal length of the camera file")
          .add("cam_prior_k1", &O::prior_k1, "1-sigma k1 of the camera file")
          .add("cam_max_model_error_px", &O::max_model_error_px,
               "[px] largest camera-model error term carried");
  return s;
}

}  // namespace

const SectionSchema<TrackerOptions>& trackerIniSchema() {
  using T = TrackerOptions;
  static const auto s =
      SectionSchema<T>()
          .add("exposure_s", &T::exposure_s, "[s] exposure, for the blur of predicted stars")
          .choice("lis_algorithm", &T::lis_algorithm, StarIdentifier::names(), "lost-in-space algorithm")
          .add("lis_min_sigma_px", &T::min_sigma_px, "[px] centroid sigma floor, lost-in-space")
          .renamed("min_sigma_px", "lis_min_sigma_px")
          .include(identifySchema(), &T::identify)
          .include(detectorSchema(), &T::detect)
          .add("cam_heal_range", &T::camera_heal_range,
               "lost-in-space heals a camera file within +-this relative focal length (0: off)")
          .include(onlineCameraSchema(), &T::online_camera)
          .choice("track_solver", &T::solver, WahbaSolver::names(), "Wahba solver while tracking")
          .renamed("solver", "track_solver lis_solver")  // it set both
          .add("track_min_sigma_px", &T::tracking_min_sigma_px,
               "[px] centroid sigma floor, tracking")
          .renamed("tracking_min_sigma_px", "track_min_sigma_px")
          .add("track_max_stars", &T::max_tracked_stars, "windows per frame")
          .renamed("max_tracked_stars", "track_max_stars")
          .add("track_min_stars", &T::min_tracked_stars, "fewer gated stars: failed frame")
          .renamed("min_tracked_stars", "track_min_stars")
          .add("track_drop_saturated", &T::drop_saturated, "saturated stars left out of the fix")
          .renamed("drop_saturated", "track_drop_saturated")
          .add("track_gate_sigma", &T::gate_sigma, "Mahalanobis gate of predicted stars")
          .renamed("gate_sigma", "track_gate_sigma")
          .add("track_edge_margin_px", &T::edge_margin_px,
               "[px] predicted stars nearer the border not windowed")
          .renamed("edge_margin_px", "track_edge_margin_px")
          .add("track_blend_separation_px", &T::blend_separation_px,
               "[px] predicted stars this close to another not windowed")
          .renamed("blend_separation_px", "track_blend_separation_px")
          .add("track_screen_pull_sigma", &T::screen_pull_sigma,
               "predicted stars a fainter uncatalogued star pulls this many sigma not windowed")
          .add("track_loss_probability", &T::loss_probability, "false-alarm rate of the loss test")
          .renamed("loss_probability", "track_loss_probability")
          .add("track_consistency_probability", &T::consistency_probability,
               "false-alarm rate of the prediction-consistency test")
          .renamed("consistency_probability", "track_consistency_probability")
          .add("track_max_failed_frames", &T::max_failed_frames,
               "failed frames in a row: lost-in-space")
          .renamed("max_failed_frames", "track_max_failed_frames")
          .add("track_reacquire_in_frame", &T::reacquire_in_frame,
               "too few stars in the windows: lost-in-space in the same frame")
          .add("track_reacquire_budget_s", &T::reacquire_budget_s,
               "[s] time lost-in-space may take in that frame; 0 = no limit")
          .add("f2f_enabled", &T::frame_to_frame,
               "propagate our own attitudes when nothing is given")
          .renamed("frame_to_frame", "f2f_enabled")
          .add("f2f_max_propagation_s", &T::max_propagation_s, "[s] older attitudes not propagated")
          .renamed("max_propagation_s", "f2f_max_propagation_s")
          .add("f2f_accel_sigma", &T::accel_sigma, "[rad/s^2] 1-sigma angular acceleration")
          .renamed("accel_sigma", "f2f_accel_sigma")
          .add("f2f_gyro_sigma", &T::gyro_sigma, "[rad/s] 1-sigma error of a given rate")
          .renamed("gyro_sigma", "f2f_gyro_sigma");
  return s;
}

const SectionSchema<PipelineOptions>& pipelineIniSchema() {
  static const auto s = SectionSchema<PipelineOptions>()
                            .add("sensor_label", &PipelineOptions::sensor_label,
                                 "label of the star-tracker observations")
                            .include(trackerIniSchema(), &PipelineOptions::tracker);
  return s;
}

std::string trackerKeyOfError(const std::string& why) {
  // The field tokens of the validation messages and their keys: a stage's options name
  // their fields "Struct.field"; TrackerOptions' own are "option 'field'" (its old key name).
  std::vector<std::pair<std::string, std::string>> tokens = {
      {"option 'identify.solver'", "lis_solver"}};
  const std::pair<const char*, const char*> prefixes[] = {
      {"detect_", "DetectorOptions."}, {"lis_", "IdentifyOptions."}, {"verify_", "VerifyOptions."}};
  for (const auto& k : trackerIniSchema().keys()) {
    tokens.emplace_back("option '" + k.name + "'", k.name);
    tokens.emplace_back("DetectorOptions." + k.name, k.name);  // the unprefixed detector keys
    for (const auto& [pre, strukt] : prefixes)
      if (k.name.rfind(pre, 0) == 0)
        tokens.emplace_back(strukt + k.name.substr(std::string(pre).size()), k.name);
  }
  for (const auto& [old_key, new_key] : trackerIniSchema().renamedKeys())
    tokens.emplace_back("option '" + old_key + "'", new_key.substr(0, new_key.find(' ')));
  // The innermost field is the last one named.
  std::size_t best_pos = 0;
  std::string best;
  for (const auto& [token, key] : tokens) {
    for (std::size_t p = why.find(token); p != std::string::npos; p = why.find(token, p + 1)) {
      const std::size_t end = p + token.size();
      const bool whole = end == why.size() ||
                         !(std::isalnum(static_cast<unsigned char>(why[end])) || why[end] == '_');
      if (whole && (best.empty() || p >= best_pos)) {
        best_pos = p;
        best = key;
      }
    }
  }
  return best;
}

void checkTrackerOptions(const IniReader& r, const std::string& sec, const TrackerOptions& o) {
  std::string why;
  if (o.isValid(&why)) return;
  const std::string key = trackerKeyOfError(why);
  throw InputError((key.empty() ? r.where(sec) : r.whereKey(sec, key)) + ": star tracker " + why);
}

void readTrackerOptions(const IniReader& r, const std::string& sec, TrackerOptions& o) {
  trackerIniSchema().read(r, sec, o);
  checkTrackerOptions(r, sec, o);
}

void readPipelineOptions(const IniReader& r, const std::string& sec, PipelineOptions& o) {
  pipelineIniSchema().read(r, sec, o);
  checkTrackerOptions(r, sec, o.tracker);
}

}  // namespace st

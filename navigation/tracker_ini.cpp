#include "navigation/tracker_ini.hpp"

#include "sensors/sim/scenario.hpp"

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/poses/CPose3D.h>

#include "common/conventions.hpp"
#include "common/errors.hpp"
#include "common/mrpt_convert.hpp"

namespace st {

const SectionSchema<FilterIniKeys>& filterIniSchema() {
  using F = FilterIniKeys;
  static const auto s =
      SectionSchema<F>()
          .add("enabled", &F::enabled,
               "false: no filter; every frame is solved lost-in-space (with the gyro's rate for "
               "its streaks) and its fix is the output, unfiltered: acquisition on its own")
          .add("arw_deg_rt_h", &F::arw_deg_rt_h, "[deg/sqrt(h)] gyro angle random walk")
          .range(0, 100)
          .add("rrw_deg_h_rt_h", &F::rrw_deg_h_rt_h, "[deg/h/sqrt(h)] gyro rate random walk")
          .range(0, 1000)
          .add("bias_sigma_deg_h", &F::bias_sigma_deg_h, "[deg/h] prior 1-sigma of the gyro bias")
          .range(0, 1e5)
          .add("gate", &F::gate, "chi-square gate of the updates")
          .add("gate_probability", &F::gate_probability, "reject when NIS > quantile(p, dof)")
          .add("max_star_vectors", &F::max_star_vectors, "stars per star-vector update at most")
          .choice("update", &F::update, {"attitude", "stars"}, "how fixes enter the filter")
          .choice("model", &F::model, {"gyro", "gyroless"},
                  "gyro: state attitude + gyro bias, propagated by GYRO samples (a run without "
                  "them has no filter); gyroless: state attitude + body rate, constant-rate "
                  "dynamics, GYRO samples not used")
          .add("rate_walk_rad_s2_rt_hz", &F::rate_walk_rad_s2_rt_hz,
               "[rad/s^2/sqrt(Hz)] gyroless: spectral density of the body-rate random walk "
               "(over T seconds the rate wanders by this x sqrt(T) per axis)")
          .range(0, 10)
          .add("rate_sigma_deg_s", &F::rate_sigma_deg_s,
               "[deg/s] gyroless: prior 1-sigma of the body rate at the first fix")
          .range(0, 360);
  return s;
}

NavigatorIniKeys NavigatorIniKeys::of(const NavigatorOptions& o) {
  NavigatorIniKeys k;
  const FusionOptions& f = o.fusion;
  k.reinit_after_rejections = f.reinit_after_rejections;
  k.reorder_window_s = f.reorder_window_s;
  k.gyro_gap_factor = f.gyro_gap_factor;
  k.max_gyro_coast_s = f.max_gyro_coast_s;
  k.rate_window_s = f.rate_window_s;
  k.max_warnings = f.max_warnings;
  const GyroHealthOptions& h = f.gyro_health;
  k.gyro_health = h.enabled;
  k.gyro_max_accel_deg_s2 = rad2deg(h.max_angular_accel_rad_s2);
  k.gyro_spike_sigmas = h.spike_sigmas;
  k.gyro_spike_median_of = h.median_of;
  k.gyro_step_after = h.step_after;
  k.gyro_health_window = h.window;
  k.gyro_noise_factor = h.noise_factor;
  k.gyro_noisy_flags = h.noisy_flags;
  k.camera_label = o.camera_label;
  k.gyro_label = o.gyro_label;
  k.truth_label = o.truth_label;
  k.star_tracker_label = o.star_tracker_label;
  k.velocity_label = o.velocity_label;
  k.velocity_aberration = f.velocity_aberration;
  k.max_velocity_age_s = f.max_velocity_age_s;
  k.head_labels = o.head_labels;
  k.head_consistency_alpha = f.head_consistency_alpha;
  return k;
}

const SectionSchema<NavigatorIniKeys>& navigatorIniSchema(bool live) {
  using K = NavigatorIniKeys;
  auto make = [](bool with_enabled) {
    auto s =
        SectionSchema<K>()
            .add("reinit_after_rejections", &K::reinit_after_rejections,
                 "gate rejections in a row -> re-initialise")
            .add("reorder_window_s", &K::reorder_window_s, "[s] events held this long to be sorted")
            .add("gyro_gap_factor", &K::gyro_gap_factor,
                 "a longer gyro interval (x nominal) is a gap")
            .add("max_gyro_coast_s", &K::max_gyro_coast_s,
                 "[s] a gyro silent longer suspends the filter (frames lost-in-space, raw fixes) "
                 "until it returns")
            .add("rate_window_s", &K::rate_window_s,
                 "[s] gyro samples averaged for the rate handed on")
            .add("max_warnings", &K::max_warnings, "warnings kept (later ones only counted)")
            .add("gyro_mount_ypr_deg", &K::gyro_mount_ypr_deg,
                 "[deg] yaw pitch roll of the gyro in the body (w_body = R w_gyro)")
            .add("gyro_health", &K::gyro_health,
                 "check every gyro sample against its datasheet noise (spikes, stuck or noisy "
                 "axes suspend the filter)")
            .add("gyro_max_accel_deg_s2", &K::gyro_max_accel_deg_s2,
                 "[deg/s^2] the body's largest angular acceleration: a faster change is a spike")
            .add("gyro_spike_sigmas", &K::gyro_spike_sigmas,
                 "a sample further than this many noise sigma from the recent median is a spike")
            .add("gyro_spike_median_of", &K::gyro_spike_median_of,
                 "accepted samples whose median a sample is compared with")
            .add("gyro_step_after", &K::gyro_step_after,
                 "flagged samples in a row that agree: a real rate step, not a spike")
            .add("gyro_health_window", &K::gyro_health_window,
                 "samples of the stuck / noisy statistics and of the recovery")
            .add("gyro_noise_factor", &K::gyro_noise_factor,
                 "an axis whose scatter exceeds this x its datasheet noise is noisy")
            .add("gyro_noisy_flags", &K::gyro_noisy_flags,
                 "spikes on one axis within the window that make it noisy")
            .add("camera_label", &K::camera_label, "rawlog label of the frames")
            .add("gyro_label", &K::gyro_label, "rawlog label of the gyro")
            .add("truth_label", &K::truth_label, "rawlog label of the truth")
            .add("star_tracker_label", &K::star_tracker_label, "rawlog label of the fixes (live)")
            .add("velocity_label", &K::velocity_label,
                 "rawlog label of the observer's velocity (CObservationIMU IMU_X/Y/Z_VEL [m/s], "
                 "inertial, relative to the Earth's centre)")
            .add("velocity_aberration", &K::velocity_aberration,
                 "correct every fix for the aberration of the observer's velocity (false: "
                 "VELOCITY samples are not used)")
            .add("max_velocity_age_s", &K::max_velocity_age_s,
                 "[s] a velocity sample older than this at a frame is not used (the frame is "
                 "not corrected, one warning)")
            .add("head_labels", &K::head_labels,
                 "camera labels of further heads beside camera_label (replay), comma-separated, in the order of "
                 "the scenario's head_sections; each head is mounted as its images' cameraPose "
                 "says, and the heads' frames of one time make one joint fix")
            .add("head_consistency_alpha", &K::head_consistency_alpha,
                 "false-alarm probability of the heads' disagreement test: heads whose fixes "
                 "disagree beyond it are not merged");
    if (with_enabled) s.add("enabled", &K::enabled, "run the filter");
    return s;
  };
  static const auto tracker_schema = make(false), live_schema = make(true);
  return live ? live_schema : tracker_schema;
}

const SectionSchema<LiveGlobalIniKeys>& liveGlobalIniSchema() {
  using K = LiveGlobalIniKeys;
  const char* grabber = "rawlog-grabber's key (not used by startracker live)";
  static const auto s =
      SectionSchema<K>()
          .add("rawlog_file", &K::rawlog_file,
               "output rawlog, relative to the working directory as -o (-o wins)")
          .add("rawlog_prefix", &K::rawlog_prefix, grabber)
          .add("time_between_launches", &K::time_between_launches, grabber)
          .add("use_sensoryframes", &K::use_sensoryframes, grabber)
          .add("GRABBER_PERIOD_MS", &K::GRABBER_PERIOD_MS, grabber)
          .add("rawlog_GZ_compress_level", &K::rawlog_GZ_compress_level, grabber)
          .add("SF_max_time_span", &K::SF_max_time_span, grabber);
  return s;
}

void applyFusionKeys(const IniReader& r, const FilterIniKeys& fk, const NavigatorIniKeys& k,
                     NavigatorOptions& n) {
  FusionOptions& f = n.fusion;
  f.filter = MekfOptions::fromDatasheet(fk.arw_deg_rt_h, fk.rrw_deg_h_rt_h, fk.bias_sigma_deg_h);
  f.filter_enabled = fk.enabled;
  f.filter.gate_enabled = fk.gate;
  f.filter.gate_probability = fk.gate_probability;
  f.filter.max_star_vectors = fk.max_star_vectors;
  f.filter.model =
      fk.model == "gyroless" ? MekfOptions::Model::kGyroless : MekfOptions::Model::kGyro;
  f.filter.rate_walk_rad_s2_rt_hz = fk.rate_walk_rad_s2_rt_hz;
  f.filter.initial_rate_sigma_rad_s = deg2rad(fk.rate_sigma_deg_s);
  f.update =
      fk.update == "stars" ? FusionOptions::Update::kStarVectors : FusionOptions::Update::kAttitude;
  f.reinit_after_rejections = k.reinit_after_rejections;
  f.reorder_window_s = k.reorder_window_s;
  f.gyro_gap_factor = k.gyro_gap_factor;
  f.max_gyro_coast_s = k.max_gyro_coast_s;
  f.rate_window_s = k.rate_window_s;
  f.max_warnings = k.max_warnings;
  f.velocity_aberration = k.velocity_aberration;
  f.max_velocity_age_s = k.max_velocity_age_s;
  GyroHealthOptions& h = f.gyro_health;
  h.enabled = k.gyro_health;
  h.max_angular_accel_rad_s2 = deg2rad(k.gyro_max_accel_deg_s2);
  h.spike_sigmas = k.gyro_spike_sigmas;
  h.median_of = k.gyro_spike_median_of;
  h.step_after = k.gyro_step_after;
  h.window = k.gyro_health_window;
  h.noise_factor = k.gyro_noise_factor;
  h.noisy_flags = k.gyro_noisy_flags;
  f.R_body_gyro = mountingPose(k.gyro_mount_ypr_deg).getRotationMatrix().asEigen();
  n.camera_label = k.camera_label;
  n.gyro_label = k.gyro_label;
  n.truth_label = k.truth_label;
  n.star_tracker_label = k.star_tracker_label;
  n.velocity_label = k.velocity_label;
  n.head_labels = k.head_labels;
  f.head_consistency_alpha = k.head_consistency_alpha;
  std::string why;
  if (!f.filter.isValid(&why)) throw InputError(r.where("filter") + ": " + why);
  if (!f.isValid(&why)) throw InputError(r.where("navigator") + " key " + why);
}

LiveIniKeys readLiveIni(const IniReader& r) {
  LiveIniKeys k;
  NavigatorOptions defaults;
  defaults.fusion.reorder_window_s = 0.5;  // live: a fix arrives after its processing time
  k.navigator = NavigatorIniKeys::of(defaults);
  std::set<std::string> sections = liveIniSections(r);
  if (r.cfg.sectionExists("scenario"))  // simulated sensors read their scenario from this file
    for (const auto& s : scenarioSectionNames(r)) sections.insert(s);
  r.onlySections(sections, "a live .ini");
  liveGlobalIniSchema().read(r, "global", k.global);
  filterIniSchema().read(r, "filter", k.filter);
  navigatorIniSchema(true).read(r, "navigator", k.navigator);
  return k;
}

std::string printLiveIni(const LiveIniKeys& k) {
  return liveGlobalIniSchema().print("global", k.global) + "\n" +
         filterIniSchema().print("filter", k.filter) + "\n" +
         navigatorIniSchema(true).print("navigator", k.navigator);
}

}  // namespace st

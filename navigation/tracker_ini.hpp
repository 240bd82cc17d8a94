/// @file tracker_ini.hpp
/// The schemas of the fusion loop's sections, shared by tracker.ini and the live app's .ini,
/// and of the live app's [global]: strict reading (config/schema.hpp) and the printed
/// effective configuration of `startracker config`.
///   [filter]     arw_deg_rt_h, rrw_deg_h_rt_h, bias_sigma_deg_h (gyro datasheet numbers ->
///                MekfOptions), gate, gate_probability, max_star_vectors, update, model
///                (gyro | gyroless), rate_walk_rad_s2_rt_hz, rate_sigma_deg_s (gyroless)
///   [navigator]  FusionOptions (reinit_after_rejections, reorder_window_s, gyro_gap_factor,
///                max_gyro_coast_s, rate_window_s, max_warnings, gyro_mount_ypr_deg -> R_body_gyro) and the
///                rawlog labels of NavigatorOptions; live: also `enabled`
///   [global]     live: rawlog_file
/// FusionOptions::R_body_camera is not a key: the navigator takes it from the pipeline's
/// sensor pose (navigator.cpp).
#pragma once
#include <string>

#include "config/ini_kind.hpp"
#include "config/schema.hpp"
#include "navigation/navigator.hpp"

namespace st {

/// [filter]: the datasheet numbers of the gyro; defaults = FusionOptions' default filter.
struct FilterIniKeys {
  bool enabled = true;  ///< false: no filter, every frame lost-in-space (FusionOptions::filter_enabled)
  double arw_deg_rt_h = 0.15;
  double rrw_deg_h_rt_h = 0.5;
  double bias_sigma_deg_h = 10.0;
  bool gate = true;
  double gate_probability = 0.999;
  int max_star_vectors = 32;
  std::string update = "attitude";
  std::string model = "gyro";             ///< "gyro" | "gyroless" (MekfOptions::Model)
  double rate_walk_rad_s2_rt_hz = 1e-3;   ///< gyroless: rate random walk density
  double rate_sigma_deg_s = 2.0;          ///< gyroless: prior 1-sigma of the body rate
};

/// [navigator]: FusionOptions' loop settings and NavigatorOptions' labels.
struct NavigatorIniKeys {
  int reinit_after_rejections = 3;
  double reorder_window_s = 0.05;
  double gyro_gap_factor = 2.5;
  double max_gyro_coast_s = 1.0;
  double rate_window_s = 0.1;
  int max_warnings = 50;
  Vec3 gyro_mount_ypr_deg = Vec3::Zero();  ///< [deg] yaw pitch roll (MRPT CPose3D) of R_body_gyro
  // The gyro health checks (fusion/gyro_health.hpp), in datasheet units.
  bool gyro_health = true;
  double gyro_max_accel_deg_s2 = 10;
  double gyro_spike_sigmas = 10;
  int gyro_spike_median_of = 5, gyro_step_after = 3, gyro_health_window = 20;
  double gyro_noise_factor = 4;
  int gyro_noisy_flags = 4;
  std::string camera_label, gyro_label, truth_label, star_tracker_label, velocity_label;
  bool velocity_aberration = true;
  double max_velocity_age_s = 10;
  std::vector<std::string> head_labels;
  double head_consistency_alpha = 1e-6;
  bool enabled = true;  ///< live only

  /// The keys of `o` (its defaults; the gyro mount as identity).
  static NavigatorIniKeys of(const NavigatorOptions& o);
};

/// The live app's [global].
struct LiveGlobalIniKeys {
  std::string rawlog_file = "live.rawlog";
  /// MRPT rawlog-grabber's own [global] keys, so one .ini serves both programs; kept as
  /// text: `live` records to rawlog_file (or -o) on its own schedule and does not use them.
  std::string rawlog_prefix, time_between_launches, use_sensoryframes, GRABBER_PERIOD_MS,
      rawlog_GZ_compress_level, SF_max_time_span;
};

const SectionSchema<FilterIniKeys>& filterIniSchema();
/// With `enabled` for the live app.
const SectionSchema<NavigatorIniKeys>& navigatorIniSchema(bool live);
const SectionSchema<LiveGlobalIniKeys>& liveGlobalIniSchema();

/// The fusion sections as the loop's options: [filter] and [navigator] into `n` (over its
/// values), then FusionOptions::isValid once, reported under [navigator].
void applyFusionKeys(const IniReader& r, const FilterIniKeys& f, const NavigatorIniKeys& k,
                     NavigatorOptions& n);

/// The live app's .ini own sections, read strictly.
struct LiveIniKeys {
  LiveGlobalIniKeys global;
  FilterIniKeys filter;
  NavigatorIniKeys navigator;
};
LiveIniKeys readLiveIni(const IniReader& r);
std::string printLiveIni(const LiveIniKeys& k);

}  // namespace st

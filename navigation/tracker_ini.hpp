/// @file tracker_ini.hpp
/// The schemas of the fusion loop's sections, shared by tracker.ini and the live app's .ini,
/// and of the live app's [global]: strict reading (config/schema.hpp) and the printed
/// effective configuration of `startracker config`. The keys are bound to the loop's own
/// options (FusionOptions, MekfOptions, GyroHealthOptions, NavigatorOptions): their defaults
/// are those structs' initialisers, and units are converted at this edge (datasheet deg/h
/// into rad/s, yaw-pitch-roll degrees into a rotation matrix). No mirror structs: a new
/// tunable is its field plus one schema line (issue 36, item 5).
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

/// The live app's [global].
struct LiveGlobalIniKeys {
  std::string rawlog_file = "live.rawlog";
  /// MRPT rawlog-grabber's own [global] keys, so one .ini serves both programs; kept as
  /// text: `live` records to rawlog_file (or -o) on its own schedule and does not use them.
  std::string rawlog_prefix, time_between_launches, use_sensoryframes, GRABBER_PERIOD_MS,
      rawlog_GZ_compress_level, SF_max_time_span;
};

/// [filter]: FusionOptions' filter (MekfOptions, gyro datasheet units) and how fixes enter.
const SectionSchema<FusionOptions>& filterIniSchema();
/// [navigator]: FusionOptions' loop settings (gyro health included) and NavigatorOptions'
/// rawlog labels.
const SectionSchema<NavigatorOptions>& navigatorIniSchema();
const SectionSchema<LiveGlobalIniKeys>& liveGlobalIniSchema();

/// [filter] and [navigator] into `n` (over its values), then the options' own checks,
/// reported under the section (MekfOptions under [filter], FusionOptions under [navigator]).
void readFusionSections(const IniReader& r, NavigatorOptions& n);
/// The two sections in ini form.
std::string printFusionSections(const NavigatorOptions& n);

/// The live app's [navigator]: the loop's, plus whether the filter runs at all.
struct LiveNavigatorKeys {
  NavigatorOptions nav;
  bool enabled = true;
};
const SectionSchema<LiveNavigatorKeys>& liveNavigatorIniSchema();

/// The live app's .ini own sections, read strictly.
struct LiveIniKeys {
  LiveGlobalIniKeys global;
  LiveNavigatorKeys navigator;  ///< [filter] and [navigator]
};
LiveIniKeys readLiveIni(const IniReader& r);
std::string printLiveIni(const LiveIniKeys& k);

}  // namespace st

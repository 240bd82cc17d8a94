#include "navigation/tracker_ini.hpp"

#include "sensors/sim/scenario.hpp"

#include <mrpt/config/CConfigFileBase.h>
#include <mrpt/poses/CPose3D.h>

#include "common/conventions.hpp"
#include "common/errors.hpp"
#include "common/mrpt_convert.hpp"

namespace st {

namespace {

// Unit conversions at the edge: the keys' units (deg, datasheet) into the options' (rad).
double degToRad(const double& d) { return deg2rad(d); }
double radToDeg(const double& r) { return rad2deg(r); }
Mat3 mountFromYpr(const Vec3& ypr_deg) { return mountingPose(ypr_deg).getRotationMatrix().asEigen(); }
Vec3 yprFromMount(const Mat3& R) {
  if (R.isIdentity(0)) return Vec3::Zero();  // prints 0 0 0, not -0
  mrpt::poses::CPose3D p;
  p.setRotationMatrix(mrpt::math::CMatrixDouble33(R));
  double yaw = 0, pitch = 0, roll = 0;
  p.getYawPitchRoll(yaw, pitch, roll);
  return Vec3(rad2deg(yaw), rad2deg(pitch), rad2deg(roll));
}

// [filter], the MekfOptions part before and after FusionOptions::update (the printed order).
SectionSchema<MekfOptions> mekfNoiseKeys() {
  using M = MekfOptions;
  namespace u = gyro_units;
  return SectionSchema<M>()
      .converted<double, double>("arw_deg_rt_h", &M::arw_rad_rt_s, u::arwToFilter,
                                 u::arwToDatasheet, "[deg/sqrt(h)] gyro angle random walk")
      .range(0, 100)
      .converted<double, double>("rrw_deg_h_rt_h", &M::rrw_rad_s_rt_s, u::rrwToFilter,
                                 u::rrwToDatasheet, "[deg/h/sqrt(h)] gyro rate random walk")
      .range(0, 1000)
      .converted<double, double>("bias_sigma_deg_h", &M::initial_bias_sigma_rad_s,
                                 u::biasToFilter, u::biasToDatasheet,
                                 "[deg/h] prior 1-sigma of the gyro bias")
      .range(0, 1e5)
      .add("gate", &M::gate_enabled, "chi-square gate of the updates")
      .add("gate_probability", &M::gate_probability, "reject when NIS > quantile(p, dof)")
      .add("max_star_vectors", &M::max_star_vectors, "stars per star-vector update at most");
}

SectionSchema<MekfOptions> mekfModelKeys() {
  using M = MekfOptions;
  return SectionSchema<M>()
      .mapped("model", &M::model, {{"gyro", M::Model::kGyro}, {"gyroless", M::Model::kGyroless}},
              "gyro: state attitude + gyro bias, propagated by GYRO samples (a run without "
              "them has no filter); gyroless: state attitude + body rate, constant-rate "
              "dynamics, GYRO samples not used")
      .add("rate_walk_rad_s2_rt_hz", &M::rate_walk_rad_s2_rt_hz,
           "[rad/s^2/sqrt(Hz)] gyroless: spectral density of the body-rate random walk "
           "(over T seconds the rate wanders by this x sqrt(T) per axis)")
      .range(0, 10)
      .converted<double, double>("rate_sigma_deg_s", &M::initial_rate_sigma_rad_s, degToRad,
                                 radToDeg, "[deg/s] gyroless: prior 1-sigma of the body rate at the first fix")
      .range(0, 360);
}

SectionSchema<GyroHealthOptions> gyroHealthKeys() {
  using H = GyroHealthOptions;
  return SectionSchema<H>()
      .add("gyro_health", &H::enabled,
           "check every gyro sample against its datasheet noise (spikes, stuck or noisy "
           "axes suspend the filter)")
      .converted<double, double>("gyro_max_accel_deg_s2", &H::max_angular_accel_rad_s2, degToRad,
                                 radToDeg,
                                 "[deg/s^2] the body's largest angular acceleration: a faster "
                                 "change is a spike")
      .add("gyro_spike_sigmas", &H::spike_sigmas,
           "a sample further than this many noise sigma from the recent median is a spike")
      .add("gyro_spike_median_of", &H::median_of,
           "accepted samples whose median a sample is compared with")
      .add("gyro_step_after", &H::step_after,
           "flagged samples in a row that agree: a real rate step, not a spike")
      .add("gyro_health_window", &H::window,
           "samples of the stuck / noisy statistics and of the recovery")
      .add("gyro_noise_factor", &H::noise_factor,
           "an axis whose scatter exceeds this x its datasheet noise is noisy")
      .add("gyro_noisy_flags", &H::noisy_flags,
           "spikes on one axis within the window that make it noisy");
}

// The options' own checks, under the section of their keys.
void checkFusion(const IniReader& r, const FusionOptions& f) {
  std::string why;
  if (!f.filter.isValid(&why)) throw InputError(r.where("filter") + ": " + why);
  if (!f.isValid(&why)) throw InputError(r.where("navigator") + " key " + why);
}

}  // namespace

const SectionSchema<FusionOptions>& filterIniSchema() {
  using F = FusionOptions;
  static const auto s =
      SectionSchema<F>()
          .add("enabled", &F::filter_enabled,
               "false: no filter; every frame is solved lost-in-space (with the gyro's rate for "
               "its streaks) and its fix is the output, unfiltered: acquisition on its own")
          .include(mekfNoiseKeys(), &F::filter)
          .mapped("update", &F::update,
                  {{"attitude", F::Update::kAttitude}, {"stars", F::Update::kStarVectors}},
                  "how fixes enter the filter")
          .include(mekfModelKeys(), &F::filter);
  return s;
}

const SectionSchema<NavigatorOptions>& navigatorIniSchema() {
  using N = NavigatorOptions;
  using F = FusionOptions;
  static const auto s =
      SectionSchema<N>()
          .include(SectionSchema<F>()
                       .add("reinit_after_rejections", &F::reinit_after_rejections,
                            "gate rejections in a row -> re-initialise")
                       .add("reorder_window_s", &F::reorder_window_s,
                            "[s] events held this long to be sorted")
                       .add("gyro_gap_factor", &F::gyro_gap_factor,
                            "a longer gyro interval (x nominal) is a gap")
                       .add("max_gyro_coast_s", &F::max_gyro_coast_s,
                            "[s] a gyro silent longer suspends the filter (frames lost-in-space, "
                            "raw fixes) until it returns")
                       .add("rate_window_s", &F::rate_window_s,
                            "[s] gyro samples averaged for the rate handed on")
                       .add("max_warnings", &F::max_warnings,
                            "warnings kept (later ones only counted)")
                       .converted<Vec3, Mat3>("gyro_mount_ypr_deg", &F::R_body_gyro, mountFromYpr,
                                              yprFromMount,
                                              "[deg] yaw pitch roll of the gyro in the body "
                                              "(w_body = R w_gyro)")
                       .include(gyroHealthKeys(), &F::gyro_health),
                   &N::fusion)
          .add("camera_label", &N::camera_label, "rawlog label of the frames")
          .add("gyro_label", &N::gyro_label, "rawlog label of the gyro")
          .add("truth_label", &N::truth_label, "rawlog label of the truth")
          .add("star_tracker_label", &N::star_tracker_label, "rawlog label of the fixes (live)")
          .add("velocity_label", &N::velocity_label,
               "rawlog label of the observer's velocity (CObservationIMU IMU_X/Y/Z_VEL [m/s], "
               "inertial, relative to the Earth's centre)")
          .include(SectionSchema<F>()
                       .add("velocity_aberration", &F::velocity_aberration,
                            "correct every fix for the aberration of the observer's velocity "
                            "(false: VELOCITY samples are not used)")
                       .add("max_velocity_age_s", &F::max_velocity_age_s,
                            "[s] a velocity sample older than this at a frame is not used (the "
                            "frame is not corrected, one warning)"),
                   &N::fusion)
          .add("head_labels", &N::head_labels,
               "camera labels of further heads beside camera_label (replay), comma-separated, in "
               "the order of the scenario's head_sections; each head is mounted as its images' "
               "cameraPose says, and the heads' frames of one time make one joint fix")
          .include(SectionSchema<F>().add(
                       "head_consistency_alpha", &F::head_consistency_alpha,
                       "false-alarm probability of the heads' disagreement test: heads whose "
                       "fixes disagree beyond it are not merged"),
                   &N::fusion);
  return s;
}

const SectionSchema<LiveNavigatorKeys>& liveNavigatorIniSchema() {
  using L = LiveNavigatorKeys;
  static const auto s = SectionSchema<L>()
                            .include(navigatorIniSchema(), &L::nav)
                            .add("enabled", &L::enabled, "run the filter");
  return s;
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

void readFusionSections(const IniReader& r, NavigatorOptions& n) {
  filterIniSchema().read(r, "filter", n.fusion);
  navigatorIniSchema().read(r, "navigator", n);
  checkFusion(r, n.fusion);
}

std::string printFusionSections(const NavigatorOptions& n) {
  return filterIniSchema().print("filter", n.fusion) + "\n" +
         navigatorIniSchema().print("navigator", n);
}

LiveIniKeys readLiveIni(const IniReader& r) {
  LiveIniKeys k;
  k.navigator.nav.fusion.reorder_window_s = 0.5;  // live: a fix arrives after its processing time
  std::set<std::string> sections = liveIniSections(r);
  if (r.cfg.sectionExists("scenario"))  // simulated sensors read their scenario from this file
    for (const auto& s : scenarioSectionNames(r)) sections.insert(s);
  r.onlySections(sections, "a live .ini");
  liveGlobalIniSchema().read(r, "global", k.global);
  filterIniSchema().read(r, "filter", k.navigator.nav.fusion);
  liveNavigatorIniSchema().read(r, "navigator", k.navigator);
  checkFusion(r, k.navigator.nav.fusion);
  return k;
}

std::string printLiveIni(const LiveIniKeys& k) {
  return liveGlobalIniSchema().print("global", k.global) + "\n" +
         filterIniSchema().print("filter", k.navigator.nav.fusion) + "\n" +
         liveNavigatorIniSchema().print("navigator", k.navigator);
}

}  // namespace st

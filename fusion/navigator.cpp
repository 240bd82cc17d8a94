#include "fusion/navigator.hpp"

#include <mrpt/config/CConfigFile.h>
#include <mrpt/obs/CObservation6DFeatures.h>
#include <mrpt/obs/CObservationIMU.h>
#include <mrpt/obs/CObservationImage.h>
#include <mrpt/system/datetime.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "catalog/star_catalog.hpp"
#include "common/conventions.hpp"
#include "common/errors.hpp"
#include "common/mrpt_convert.hpp"
#include "sensors/mrpt/ini_reader.hpp"
#include "sensors/mrpt/pipeline_ini.hpp"
#include "sensors/sim/sim_observations.hpp"

namespace st {

namespace {

enum Kind { kGyro = 0, kCamera = 1, kTruth = 2, kOther = 3 };

std::string fmtTime(double t) {
  char b[64];
  std::snprintf(b, sizeof b, "t = %.6f s", t);
  return b;
}

}  // namespace

// ---- options ---------------------------------------------------------------------------

void NavigatorOptions::validate() const {
  auto bad = [](const std::string& key, const std::string& why) {
    throw InputError("navigator option '" + key + "': " + why);
  };
  pipeline.trackerOptions().validate();
  std::string err;
  if (!filter.isValid(&err)) bad("filter", err);
  if (update != "attitude" && update != "stars") bad("update", "'" + update + "': attitude|stars");
  if (reinit_after_rejections < 1) bad("reinit_after_rejections", "must be >= 1");
  if (!(reorder_window_s >= 0)) bad("reorder_window_s", "must be >= 0");
  if (!(gyro_gap_factor > 1)) bad("gyro_gap_factor", "must be > 1");
}

namespace {

std::string resolvePath(const std::string& p, const std::string& base_dir) {
  if (p.empty() || std::filesystem::path(p).is_absolute()) return p;
  return (std::filesystem::path(base_dir) / p).string();
}

}  // namespace

TrackerConfig TrackerConfig::load(const std::string& path) {
  if (!std::filesystem::is_regular_file(path))
    throw InputError(path + ": tracker config not found");
  mrpt::config::CConfigFile cfg(path);
  const std::string dir = std::filesystem::path(path).parent_path().string();
  return fromConfig(cfg, path, dir.empty() ? "." : dir);
}

TrackerConfig TrackerConfig::fromConfig(const mrpt::config::CConfigFileBase& cfg,
                                        const std::string& source, const std::string& base_dir) {
  const IniReader r{cfg, source};
  TrackerConfig c;
  c.source = source;
  r.onlyKeys("filter", {"arw_deg_rt_h", "rrw_deg_h_rt_h", "bias_sigma_deg_h", "gate_probability",
                        "gate", "update", "max_star_vectors"});
  r.onlyKeys("navigator", {"reinit_after_rejections", "reorder_window_s", "gyro_gap_factor",
                           "camera_label", "gyro_label", "truth_label"});
  r.onlyKeys("pipeline", pipelineIniKeys());
  r.onlyKeys("database", {"path", "catalog", "mag_limit", "epoch_jyear", "aberration"});

  NavigatorOptions& n = c.nav;
  // [filter]: gyro datasheet numbers.
  n.filter = MekfOptions::fromDatasheet(r.num("filter", "arw_deg_rt_h", 0.15),
                                        r.num("filter", "rrw_deg_h_rt_h", 0.5),
                                        r.num("filter", "bias_sigma_deg_h", 10.0));
  n.filter.gate_probability = r.num("filter", "gate_probability", n.filter.gate_probability);
  n.filter.gate_enabled = r.boolean("filter", "gate", n.filter.gate_enabled);
  n.filter.max_star_vectors = r.integer("filter", "max_star_vectors", n.filter.max_star_vectors);
  n.update = r.str("filter", "update", n.update);
  std::string err;
  if (!n.filter.isValid(&err)) throw InputError(source + ": [filter]: " + err);
  if (n.update != "attitude" && n.update != "stars")
    throw InputError(r.where("filter", "update") + " = '" + n.update + "': attitude or stars");

  // [navigator]
  n.reinit_after_rejections =
      r.integer("navigator", "reinit_after_rejections", n.reinit_after_rejections);
  n.reorder_window_s = r.num("navigator", "reorder_window_s", n.reorder_window_s);
  n.gyro_gap_factor = r.num("navigator", "gyro_gap_factor", n.gyro_gap_factor);
  n.camera_label = r.str("navigator", "camera_label", n.camera_label);
  n.gyro_label = r.str("navigator", "gyro_label", n.gyro_label);
  n.truth_label = r.str("navigator", "truth_label", n.truth_label);

  // [pipeline]
  readPipelineOptions(r, "pipeline", n.pipeline);
  try {
    n.validate();
  } catch (const InputError& e) {
    throw InputError(source + ": " + e.what());
  }

  // [database]
  c.database.path = resolvePath(r.str("database", "path", ""), base_dir);
  c.database.catalog = resolvePath(r.str("database", "catalog", ""), base_dir);
  c.database.mag_limit = r.num("database", "mag_limit", c.database.mag_limit);
  c.database.epoch_jyear = r.num("database", "epoch_jyear", c.database.epoch_jyear);
  c.database.aberration = r.boolean("database", "aberration", c.database.aberration);

  // [camera]
  if (cfg.sectionExists("camera")) c.camera = CameraModel::loadIni(cfg, "camera", source);
  return c;
}

StarDatabase makeDatabase(const DatabaseSource& src, const CameraModel& camera,
                          double data_epoch_jyear) {
  if (!src.path.empty()) return StarDatabase::load(src.path);
  const std::string cat_path =
      src.catalog.empty() ? StarDatabase::defaultCatalogPath() : src.catalog;
  const double max_diag = 2.0 * camera.halfDiagonalFov();
  DatabaseParams p{};
  p.max_pair_angle = max_diag + deg2rad(0.2);
  p.mag_limit = src.mag_limit;
  p.epoch_jyear = src.epoch_jyear > 0 ? src.epoch_jyear : data_epoch_jyear;
  p.aberration = src.aberration;
  p.double_star_sep = 1.5 * camera.pixelScale();  // unresolved doubles (as `solve`)
  p.max_stars_per_region = 0;
  p.neighbour_radius = max_diag / 2;
  return StarDatabase::build(loadCatalog(cat_path), p);
}

// ---- CSV -----------------------------------------------------------------------------

std::string navStepCsvHeader() {
  return "t_s,has_frame,mode,stars,frame_ms,initialized,reinit,qw,qx,qy,qz,"
         "bias_x_deg_h,bias_y_deg_h,bias_z_deg_h,sigma_x_arcsec,sigma_y_arcsec,sigma_z_arcsec,"
         "sigma_bias_x_deg_h,sigma_bias_y_deg_h,sigma_bias_z_deg_h,update,"
         "innov_x_arcsec,innov_y_arcsec,innov_z_arcsec,innov_sigma_x_arcsec,"
         "innov_sigma_y_arcsec,innov_sigma_z_arcsec,nis,nis_dof,has_truth,err_arcsec,"
         "err_cross_arcsec,err_roll_arcsec,nees,fix_err_arcsec,sigma_cross_arcsec,"
         "sigma_roll_arcsec,fix_nees,misidentified,blend_claims";
}

std::string navStepCsvRow(const NavStep& s) {
  const double deg_h = kDegPerRad * 3600.0;
  std::ostringstream o;
  o.precision(10);
  o << s.t << ',' << int(s.has_frame) << ','
    << (s.has_frame ? toString(s.mode) : "no-frame") << ',' << s.stars_matched << ','
    << s.frame_time_s * 1e3 << ',' << int(s.initialized) << ',' << int(s.reinitialized);
  const Quat q = canonical(s.q_ib);
  o << ',' << q.w() << ',' << q.x() << ',' << q.y() << ',' << q.z();
  for (int i = 0; i < 3; ++i) o << ',' << s.bias[i] * deg_h;
  for (int i = 0; i < 3; ++i) o << ',' << rad2arcsec(s.sigma_att[i]);
  for (int i = 0; i < 3; ++i) o << ',' << s.sigma_bias[i] * deg_h;
  o << ',' << s.update;
  for (int i = 0; i < 3; ++i)
    o << ',' << (s.innovation.size() > i ? rad2arcsec(s.innovation[i]) : 0.0);
  for (int i = 0; i < 3; ++i) {
    o << ','
      << (s.innovation_cov.rows() > i ? rad2arcsec(std::sqrt(s.innovation_cov(i, i))) : 0.0);
  }
  o << ',' << s.nis << ',' << s.nis_dof << ',' << int(s.has_truth);
  o << ',' << rad2arcsec(s.error.total) << ',' << rad2arcsec(s.error.cross_boresight) << ','
    << rad2arcsec(s.error.roll) << ',' << s.nees << ','
    << (s.fix && s.has_truth ? rad2arcsec(s.fix_error.total) : 0.0);
  const AttitudeSigma sg = attitudeSigma(s.P_att);
  o << ',' << rad2arcsec(sg.cross_boresight) << ',' << rad2arcsec(sg.roll);
  o << ',' << (s.fix && s.has_truth ? s.fix_nees : 0.0) << ',' << s.misidentified << ',' << s.blend_claims;
  return o.str();
}

// ---- navigator -------------------------------------------------------------------------

struct Navigator::Item {
  mrpt::Clock::time_point t;
  int kind;
  uint64_t seq;
  mrpt::obs::CObservation::Ptr obs;
  // std heap is a max-heap: "greater" means later.
  bool operator<(const Item& o) const {
    if (t != o.t) return t > o.t;
    if (kind != o.kind) return kind > o.kind;
    return seq > o.seq;
  }
};

Navigator::Navigator(const StarDatabase& db, const CameraModel& camera, NavigatorOptions options)
    : db_(db), opts_(std::move(options)), filter_((opts_.validate(), opts_.filter)) {
  pipeline_ = std::make_unique<StarTracker>(db, camera, opts_.pipeline.trackerOptions());
  // Catalog id -> star index, for star-vector updates.
  std::vector<std::pair<uint32_t, uint32_t>> m;
  m.reserve(db.stars().size());
  for (uint32_t i = 0; i < db.stars().size(); ++i) m.emplace_back(db.stars()[i].id, i);
  std::sort(m.begin(), m.end());
  for (const auto& [id, i] : m) {
    id_to_index_keys_.push_back(id);
    id_to_index_vals_.push_back(i);
  }
}

Navigator::~Navigator() = default;

double Navigator::secondsFromStart(mrpt::Clock::time_point t) const {
  return t0_ ? mrpt::system::timeDifference(*t0_, t) : 0.0;
}

void Navigator::warn(const std::string& msg) {
  ++warning_count_;
  if (static_cast<int>(warnings_.size()) < opts_.max_warnings) warnings_.push_back(msg);
}

int Navigator::kindOf(const mrpt::obs::CObservation& obs) const {
  if (obs.sensorLabel == opts_.gyro_label && dynamic_cast<const mrpt::obs::CObservationIMU*>(&obs))
    return kGyro;
  if (obs.sensorLabel == opts_.camera_label &&
      dynamic_cast<const mrpt::obs::CObservationImage*>(&obs))
    return kCamera;
  if (obs.sensorLabel == opts_.truth_label &&
      dynamic_cast<const mrpt::obs::CObservation6DFeatures*>(&obs))
    return kTruth;
  return kOther;
}

void Navigator::push(const mrpt::obs::CObservation::Ptr& obs) {
  if (!obs) return;
  const int kind = kindOf(*obs);
  if (kind == kOther) return;  // not ours (e.g. STAR_TRACKER of an earlier replay)
  if (!t0_) t0_ = obs->timestamp;
  const double t = secondsFromStart(obs->timestamp);
  const std::pair<mrpt::Clock::time_point, int> key{obs->timestamp, kind};
  if (last_processed_ && key <= *last_processed_) {
    warn(std::string(key == *last_processed_ ? "duplicate" : "out-of-order") + " " +
         obs->sensorLabel + " observation at " + fmtTime(t) +
         (key == *last_processed_ ? "" : " (already processed up to " +
                                              fmtTime(secondsFromStart(last_processed_->first)) +
                                              ")") +
         ": dropped");
    return;
  }
  for (const Item& it : queue_) {
    if (it.t == obs->timestamp && it.kind == kind) {
      warn("duplicate " + obs->sensorLabel + " observation at " + fmtTime(t) + ": dropped");
      return;
    }
  }
  queue_.push_back({obs->timestamp, kind, seq_++, obs});
  std::push_heap(queue_.begin(), queue_.end());
  newest_t_ = std::max(newest_t_, t);
  while (!queue_.empty() &&
         secondsFromStart(queue_.front().t) <= newest_t_ - opts_.reorder_window_s) {
    std::pop_heap(queue_.begin(), queue_.end());
    Item it = std::move(queue_.back());
    queue_.pop_back();
    process(it.obs, it.kind);
  }
}

void Navigator::flush() {
  while (!queue_.empty()) {
    std::pop_heap(queue_.begin(), queue_.end());
    Item it = std::move(queue_.back());
    queue_.pop_back();
    process(it.obs, it.kind);
  }
  finishPending();
}

void Navigator::process(const mrpt::obs::CObservation::Ptr& obs, int kind) {
  last_processed_ = {obs->timestamp, kind};
  if (pending_ && pending_->stamp != obs->timestamp) finishPending();
  const double t = secondsFromStart(obs->timestamp);
  switch (kind) {
    case kGyro: onGyro(*obs, t); break;
    case kCamera: onCamera(*obs, t); break;
    case kTruth: onTruth(*obs, t); break;
    default: break;
  }
}

void Navigator::onGyro(const mrpt::obs::CObservation& obs, double t) {
  const Vec3 rate = rateFromObservation(static_cast<const mrpt::obs::CObservationIMU&>(obs));
  if (!rate.allFinite()) {
    warn("GYRO observation at " + fmtTime(t) + " has a non-finite rate: dropped");
    return;
  }
  double dt = 0;
  if (last_gyro_t_) {
    dt = t - *last_gyro_t_;
    if (dt > 0 && (gyro_dt_nominal_ == 0 || dt < gyro_dt_nominal_)) gyro_dt_nominal_ = dt;
  }
  const bool gap = last_gyro_t_ && gyro_dt_nominal_ > 0 &&
                   dt > opts_.gyro_gap_factor * gyro_dt_nominal_;
  if (gap) {
    char b[160];
    std::snprintf(b, sizeof b, "gyro gap of %.3f s ending at %s: coasted", dt, fmtTime(t).c_str());
    warn(b);
    // The sample is the mean rate over its own interval only: coast up to its start.
    if (filter_.initialized()) coastTo(t - gyro_dt_nominal_);
  }
  in_gap_ = false;
  last_gyro_t_ = t;
  recent_rates_[recent_next_ % recent_rates_.size()] = rate;
  ++recent_next_;
  if (!filter_.initialized() || t <= filter_.time()) return;
  filter_.propagate(rate, t);
}

Vec3 Navigator::recentMeanRate() const {
  const std::size_t n = std::min<std::size_t>(recent_next_, recent_rates_.size());
  Vec3 m = Vec3::Zero();
  for (std::size_t i = 0; i < n; ++i) m += recent_rates_[i];
  return n ? Vec3(m / double(n)) : filter_.bias();
}

void Navigator::coastTo(double t) {
  if (!filter_.initialized() || !(t > filter_.time())) return;
  // Without gyro samples the rate is held at the mean of the last samples. That rate's error
  // is constant over the coast, not white: its variance sigma_v^2 / T_mean (T_mean = the
  // averaging time) grows the attitude variance by tau^2 sigma_v^2 / T_mean on top of the
  // filter's own process noise (which models the white rate noise of real samples).
  const std::size_t n = std::min<std::size_t>(recent_next_, recent_rates_.size());
  const double t_mean = std::max(1.0, double(n)) * std::max(gyro_dt_nominal_, 1e-3);
  const double tau = t - filter_.time();
  const double sv = filter_.options().arw_rad_rt_s;
  Mat6 P = filter_.covariance();
  P.topLeftCorner<3, 3>() += Mat3::Identity() * (tau * tau * sv * sv / t_mean);
  const Vec3 rate = recentMeanRate();
  filter_.initialize(filter_.time(), filter_.attitude(), filter_.bias(), P);
  filter_.propagate(rate, t);
}

bool Navigator::gyroStale(double t) const {
  return last_gyro_t_ && gyro_dt_nominal_ > 0 &&
         t - *last_gyro_t_ > opts_.gyro_gap_factor * gyro_dt_nominal_;
}

void Navigator::fillFilterState(NavStep& s, double t) const {
  s.initialized = filter_.initialized();
  if (!s.initialized) return;
  MekfPrediction p;
  if (t == filter_.time()) {
    p.q_ib = filter_.attitude();
    p.bias = filter_.bias();
    p.P = filter_.covariance();
  } else {
    p = filter_.predictAt(t);
  }
  s.q_ib = canonical(p.q_ib);
  s.bias = p.bias;
  s.P_att = p.P.topLeftCorner<3, 3>();
  s.sigma_att = s.P_att.diagonal().cwiseMax(0.0).cwiseSqrt();
  s.sigma_bias = p.P.bottomRightCorner<3, 3>().diagonal().cwiseMax(0.0).cwiseSqrt();
}

void Navigator::initializeFrom(const CObservationStarTracker& fix, double t) {
  if (filter_.initialized()) {
    // Keep what the filter learned about the bias; the attitude restarts from the fix.
    filter_.resetAttitude(t, fix.q_ib, fix.cov_body);
    ++reinits_;
  } else {
    filter_.initialize(t, fix.q_ib, fix.cov_body);
  }
  reinit_pending_ = false;
}

MekfUpdateResult Navigator::update(const CObservationStarTracker& fix) {
  if (opts_.update == "attitude" || fix.stars.size() < 2) {
    return filter_.updateAttitude(fix.q_ib, fix.cov_body);
  }
  // Tight coupling: per-star sigma from the fix covariance. For n stars of equal sigma the
  // QUEST information matrix is sum (I - b b^T) / sigma^2, whose trace is 2 n / sigma^2
  // (seed 004 §6 covariance of the attitude solution).
  const Mat3 info = fix.cov_body.inverse();
  const double n = static_cast<double>(fix.stars.size());
  const double sigma = std::sqrt(2.0 * n / std::max(info.trace(), 1e-300));
  const auto& R = fix.sensor_pose.getRotationMatrix();
  Mat3 R_bc;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) R_bc(r, c) = R(r, c);
  std::vector<StarVectorMeasurement> meas;
  for (const MatchedStar& m : fix.stars) {
    const auto it =
        std::lower_bound(id_to_index_keys_.begin(), id_to_index_keys_.end(), m.catalog_id);
    if (it == id_to_index_keys_.end() || *it != m.catalog_id) continue;
    const uint32_t idx = id_to_index_vals_[it - id_to_index_keys_.begin()];
    meas.push_back(StarVectorMeasurement::fromSigma((R_bc * m.v_cam).normalized(),
                                                    db_.stars()[idx].u_i, sigma));
  }
  if (meas.empty()) return filter_.updateAttitude(fix.q_ib, fix.cov_body);
  return filter_.updateStarVectors(meas);
}

void Navigator::onCamera(const mrpt::obs::CObservation& obs, double t) {
  auto& io = const_cast<mrpt::obs::CObservationImage&>(
      static_cast<const mrpt::obs::CObservationImage&>(obs));
  NavStep s;
  s.stamp = obs.timestamp;
  s.t = t;
  cv::Mat image;
  try {
    io.image.forceLoad();
    image = io.image.asCvMatRef();
  } catch (const std::exception& e) {
    warn("CAMERA image at " + fmtTime(t) + " cannot be loaded (" +
         std::string(e.what()).substr(0, 200) + "): frame skipped");
    return;
  }
  if (image.empty()) {
    warn("CAMERA observation at " + fmtTime(t) + " has an empty image: frame skipped");
    return;
  }
  if (image.channels() == 3) {
    cv::Mat grey;
    cv::cvtColor(image, grey, cv::COLOR_BGR2GRAY);
    image = grey;
  }
  if (filter_.initialized() && gyroStale(t)) {
    if (!in_gap_) {
      warn("gyro gap: no GYRO sample since " + fmtTime(*last_gyro_t_) + " at the frame at " +
           fmtTime(t) + ": coasting on the mean of the last rates");
      in_gap_ = true;
    }
    coastTo(t);
  }
  FrameInputs in;
  if (filter_.initialized() && !reinit_pending_) {
    const MekfPrediction pred = filter_.predictAt(t);
    AttitudePrediction ap;
    ap.q_ib = pred.q_ib;
    ap.cov_body = pred.attitudeCov();
    ap.rate_body = recentMeanRate() - pred.bias;
    in.prediction = ap;
  } else if (recent_next_ > 0 && !gyroStale(t)) {
    // No attitude yet, but the gyro's rate tells lost-in-space how the stars streak (the
    // unknown bias, a few deg/h, is nothing next to a streak).
    in.rate_body = recentMeanRate();
  }
  CObservationStarTracker::Ptr st =
      observationFromFrame(pipeline_->process(image, t, in), obs.timestamp,
                           opts_.pipeline.sensor_label, opts_.pipeline.sensor_pose);
  if (io.image.isExternallyStored()) io.image.unload();
  s.has_frame = true;
  s.mode = st->mode;
  s.reason = st->reason;
  s.stars_matched = static_cast<int>(st->stars.size());
  s.frame_time_s = st->timings.total;
  if (st->hasAttitude()) {
    s.fix = true;
    s.q_fix = st->q_ib;
    s.cov_fix = st->cov_body;
    const bool lis = st->mode == StarTrackerMode::kLostInSpace;
    if (!filter_.initialized() || (reinit_pending_ && lis)) {
      initializeFrom(*st, t);
      s.reinitialized = true;
    } else if (!reinit_pending_) {
      if (t > filter_.time()) filter_.predictTo(t);
      const MekfUpdateResult u = update(*st);
      s.update = u.accepted ? "accepted" : "rejected";
      s.innovation = u.innovation;
      s.innovation_cov = u.innovation_cov;
      s.nis = u.nis;
      s.nis_dof = u.dof;
      if (!u.accepted) {
        if (!u.reason.empty()) s.reason += (s.reason.empty() ? "" : "; ") + u.reason;
        if (filter_.consecutiveRejections() >= opts_.reinit_after_rejections) {
          warn(std::to_string(filter_.consecutiveRejections()) +
               " star-tracker fixes in a row rejected by the filter at " + fmtTime(t) +
               ": re-initialising from lost-in-space");
          if (lis) {
            initializeFrom(*st, t);
            s.reinitialized = true;
          } else {
            pipeline_->reset();
            reinit_pending_ = true;
          }
        }
      }
    }
  }
  fillFilterState(s, t);
  pending_ = std::move(s);
  pending_obs_ = st;
}

namespace {
/// Scores the sensor's identities against the truth's star list (NavStep::misidentified,
/// NavStep::blend_claims). Two true stars closer than `unresolved_px` make one image peak
/// (two Gaussian PSFs of sigma s merge below ~2 s); the database merges such doubles under
/// the brighter member's id, so naming either member of the pair is right.
/// 2 PSF sigma of the simulated scenes (their sensors' psf_sigma_px is 1.0). The truth does
/// not carry the PSF, and the detector's guess (1.2 px) would score more leniently.
constexpr double kUnresolvedSeparationPx = 2.0;

void scoreIdentities(const CObservationStarTracker& st, const FrameTruth& truth,
                     double unresolved_px, NavStep& s) {
  for (const MatchedStar& m : st.stars) {
    const TrueStar* nearest = nullptr;
    const TrueStar* claimed = nullptr;
    for (const TrueStar& t : truth.stars) {
      if (!nearest || (t.px - m.px).squaredNorm() < (nearest->px - m.px).squaredNorm())
        nearest = &t;
      if (t.id == m.catalog_id) claimed = &t;
    }
    if (claimed == nearest) continue;
    if (claimed && (claimed->px - nearest->px).norm() < unresolved_px) {
      ++s.blend_claims;
    } else {
      ++s.misidentified;
    }
  }
}
}  // namespace

void Navigator::onTruth(const mrpt::obs::CObservation& obs, double t) {
  const FrameTruth truth =
      truthFromObservation(static_cast<const mrpt::obs::CObservation6DFeatures&>(obs));
  if (!pending_ || pending_->stamp != obs.timestamp) {
    finishPending();
    NavStep s;  // a frame slot without a frame: the filter's prediction there
    s.stamp = obs.timestamp;
    s.t = t;
    fillFilterState(s, t);
    pending_ = std::move(s);
    pending_obs_.reset();
  }
  NavStep& s = *pending_;
  s.has_truth = true;
  s.q_true = truth.q_ib;
  if (s.initialized) {
    s.error = attitudeError(s.q_ib, s.q_true);
    s.nees = attitudeNees(s.q_ib, s.P_att, s.q_true);
  }
  if (s.fix) {
    s.fix_error = attitudeError(s.q_fix, s.q_true);
    s.fix_nees = attitudeNees(s.q_fix, s.cov_fix, s.q_true);
  }
  if (pending_obs_ && !truth.stars.empty()) {
    scoreIdentities(*pending_obs_, truth, kUnresolvedSeparationPx, s);
  }
  finishPending();
}

void Navigator::finishPending() {
  if (!pending_) return;
  if (callback_) callback_(*pending_, pending_obs_);
  if (keep_steps_) steps_.push_back(std::move(*pending_));
  pending_.reset();
  pending_obs_.reset();
}

}  // namespace st

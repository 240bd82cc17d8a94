#include "navigation/navigator.hpp"

#include <mrpt/obs/CObservation6DFeatures.h>
#include <mrpt/obs/CObservationIMU.h>
#include <mrpt/obs/CObservationImage.h>
#include <mrpt/system/datetime.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <opencv2/imgproc.hpp>

#include "common/check.hpp"
#include "common/errors.hpp"
#include "navigation/truth_scoring.hpp"
#include "sensors/mrpt/rawlog_contract.hpp"

namespace st {

namespace {

FusionOptions validatedFusion(const NavigatorOptions& o) {
  std::string why;
  if (!o.isValid(&why)) throw InputError("navigator option " + why);
  return o.fusion;
}

/// Catalog id -> inertial direction, for star-vector updates (sorted ids, binary search).
FusionLoop::StarDirection starDirections(const StarDatabase& db) {
  auto ids = std::make_shared<std::vector<std::pair<uint32_t, uint32_t>>>();
  ids->reserve(db.stars().size());
  for (uint32_t i = 0; i < db.stars().size(); ++i) ids->emplace_back(db.stars()[i].id, i);
  std::sort(ids->begin(), ids->end());
  return [ids, &db](uint32_t id) -> std::optional<Vec3> {
    const auto it = std::lower_bound(ids->begin(), ids->end(), std::make_pair(id, uint32_t(0)));
    if (it == ids->end() || it->first != id) return std::nullopt;
    return db.stars()[it->second].u_i;
  };
}

/// A frame's outcome into a step or one head's part of it (NavStep, NavHead).
template <class Step>
void copyFrame(const FrameResult& r, Step& s) {
  s.mode = r.mode;
  s.failure = r.failure;
  s.stars_matched = static_cast<int>(r.stars.size());
  s.fix = r.hasAttitude();
  if (s.fix) {
    s.q_fix = r.q_ib;
    s.cov_fix = r.cov_body;
  }
}

bool samePose(const mrpt::poses::CPose3D& a, const mrpt::poses::CPose3D& b) {
  return (a.getRotationMatrix().asEigen() - b.getRotationMatrix().asEigen()).norm() < 1e-9;
}

}  // namespace

std::string headFixLabel(const std::string& first_fix_label, const std::string& camera_label) {
  return first_fix_label + "_" + camera_label;
}

bool isGyroObservation(const mrpt::obs::CObservation& obs, const NavigatorOptions& o) {
  return obs.sensorLabel == o.gyro_label && dynamic_cast<const mrpt::obs::CObservationIMU*>(&obs);
}

bool NavigatorOptions::isValid(std::string* why) const {
  if (!velocity_label.empty() && velocity_label == gyro_label) {
    if (why) *why = "'velocity_label': the same as gyro_label ('" + gyro_label + "')";
    return false;
  }
  for (std::size_t i = 0; i < head_labels.size(); ++i) {
    const std::string& l = head_labels[i];
    const bool clash = l.empty() || l == camera_label || l == gyro_label || l == truth_label ||
                       l == velocity_label ||
                       std::find(head_labels.begin(), head_labels.begin() + i, l) !=
                           head_labels.begin() + i;
    if (clash) {
      if (why) *why = "'head_labels': '" + l + "' is empty or names another sensor or head";
      return false;
    }
  }
  return fusion.isValid(why) && pipeline.trackerOptions().isValid(why);
}

Navigator::Navigator(const StarDatabase& db, const CameraModel& camera, NavigatorOptions options,
                     Source source)
    : db_(db),
      opts_(std::move(options)),
      source_(source),
      camera_(camera),
      loop_(validatedFusion(opts_), starDirections(db)) {
  // A head's fixes: replay writes them under the pipeline's label, live reads them under the
  // star tracker sensors' (the first head's label, then <it>_<camera label>).
  const std::string& fixes = source_ == Source::kCameraFrames ? opts_.pipeline.sensor_label
                                                               : opts_.star_tracker_label;
  heads_.resize(1 + opts_.head_labels.size());
  heads_[0].label = opts_.camera_label;
  heads_[0].fix_label = fixes;
  for (std::size_t h = 1; h < heads_.size(); ++h) {
    heads_[h].label = opts_.head_labels[h - 1];
    heads_[h].fix_label = headFixLabel(fixes, heads_[h].label);
  }
  if (source_ == Source::kCameraFrames) {
    // Checked once here: a head's tracker is made at its first image.
    TrackerOptions t = opts_.pipeline.trackerOptions();
    t.R_body_cam.setIdentity();
    std::string why;
    if (!t.isValid(&why)) throw InputError("navigator option " + why);
    loop_.setFrameProcessor(
        [this](uint64_t tag, double t, const FrameInputs& in) { return processFrame(tag, t, in); });
  }
  loop_.setStepCallback([this](const FusionStep& s) { onStep(s); });
}

Navigator::~Navigator() = default;

double Navigator::secondsFromStart(mrpt::Clock::time_point t) const {
  return t0_ ? mrpt::system::timeDifference(*t0_, t) : 0.0;
}

void Navigator::warn(const std::string& msg) {
  if (static_cast<int>(own_warnings_.size()) < opts_.fusion.max_warnings)
    own_warnings_.push_back(msg);
}

std::vector<std::string> Navigator::warnings() const {
  std::vector<std::string> all = own_warnings_;
  all.insert(all.end(), loop_.warnings().begin(), loop_.warnings().end());
  return all;
}

bool Navigator::isFixLabel(const std::string& label) const {
  return std::any_of(heads_.begin(), heads_.end(),
                     [&](const auto& h) { return h.fix_label == label; });
}

int Navigator::warningCount() const {
  return loop_.warningCount() + static_cast<int>(own_warnings_.size());
}

Navigator::Kind Navigator::kindOf(const mrpt::obs::CObservation& obs, int* head) const {
  const std::string& l = obs.sensorLabel;
  if (isGyroObservation(obs, opts_)) return kGyro;
  if (source_ == Source::kCameraFrames && dynamic_cast<const mrpt::obs::CObservationImage*>(&obs)) {
    for (std::size_t h = 0; h < heads_.size(); ++h) {
      if (heads_[h].label != l) continue;
      if (head) *head = static_cast<int>(h);
      return kCamera;
    }
  }
  if (source_ == Source::kStarTrackerFixes && dynamic_cast<const CObservationStarTracker*>(&obs)) {
    for (std::size_t h = 0; h < heads_.size(); ++h) {
      if (heads_[h].fix_label != l) continue;
      if (head) *head = static_cast<int>(h);
      return kFix;
    }
  }
  if (l == opts_.truth_label && dynamic_cast<const mrpt::obs::CObservation6DFeatures*>(&obs))
    return kTruth;
  if (!opts_.velocity_label.empty() && l == opts_.velocity_label &&
      dynamic_cast<const mrpt::obs::CObservationIMU*>(&obs))
    return kVelocity;
  return kOther;
}

void Navigator::push(const mrpt::obs::CObservation::Ptr& obs) {
  if (!obs) return;
  int head = 0;
  const Kind kind = kindOf(*obs, &head);
  if (kind == kOther) return;  // not ours (e.g. STAR_TRACKER of an earlier replay)
  if (!t0_) t0_ = obs->timestamp;
  const double t = secondsFromStart(obs->timestamp);
  const uint64_t tag = next_tag_++;
  switch (kind) {
    case kGyro:
      loop_.pushGyro(t, rateFromObservation(static_cast<const mrpt::obs::CObservationIMU&>(*obs)));
      return;
    case kCamera:
      held_[tag] = obs;
      head_of_[tag] = head;
      loop_.pushFrame(t, tag, head);
      return;
    case kFix:
      held_[tag] = obs;
      loop_.pushFix(t, tag, frameFromObservation(static_cast<const CObservationStarTracker&>(*obs)),
                    head);
      return;
    case kTruth:
      held_[tag] = obs;
      loop_.pushMarker(t, tag);
      return;
    case kVelocity:
      if (const auto v = velocityFromObservation(static_cast<const mrpt::obs::CObservationIMU&>(*obs))) {
        loop_.pushVelocity(t, *v);
      } else {
        warn(opts_.velocity_label + " observation at " + formatLoopTime(t) +
             " without IMU_X_VEL, IMU_Y_VEL and IMU_Z_VEL: dropped");
      }
      return;
    default: return;
  }
}

void Navigator::flush() {
  loop_.flush();
  finishPending();
  held_.clear();
  head_of_.clear();
  frame_obs_.clear();
}

FrameInputs Navigator::frameInputs(mrpt::Clock::time_point t) const {
  if (!t0_) return {};
  return loop_.frameInputs(secondsFromStart(t));
}

void Navigator::processBefore(mrpt::Clock::time_point t) {
  if (t0_) loop_.processBefore(secondsFromStart(t));
}

FrameResult Navigator::processFrame(uint64_t tag, double t, const FrameInputs& in) {
  const auto it = held_.find(tag);
  ST_ASSERT(it != held_.end());
  auto& io = static_cast<mrpt::obs::CObservationImage&>(*it->second);
  Head& head = headOf(io, head_of_.at(tag));
  return processImage(head, io, t, in, frame_obs_[tag]);
}

Navigator::Head& Navigator::headOf(const mrpt::obs::CObservationImage& io, int index) {
  Head& head = heads_[static_cast<std::size_t>(index)];
  if (!head.tracker) {
    // MRPT's convention: the sensor's pose on the vehicle travels with its observations.
    head.mount = io.cameraPose;
    TrackerOptions t = opts_.pipeline.trackerOptions();
    t.R_body_cam = head.mount.getRotationMatrix().asEigen();
    head.tracker = std::make_unique<StarTracker>(db_, camera_, t);
  } else if (!samePose(head.mount, io.cameraPose)) {
    if (!head.pose_warned)
      warn(head.label + " observation at " + formatLoopTime(secondsFromStart(io.timestamp)) +
           ": its cameraPose differs from the head's first image; the first one's mounting is "
           "kept (warned once)");
    head.pose_warned = true;
  }
  return head;
}

FrameResult Navigator::processImage(Head& head, mrpt::obs::CObservationImage& io, double t,
                                    const FrameInputs& in, CObservationStarTracker::Ptr& out_obs) {
  FrameResult failed;
  failed.failure = FrameFailure::kNoImage;
  auto skipped = [&](const std::string& why) {
    failed.detail = why;
    warn(head.label + " observation at " + formatLoopTime(t) + ": " + why + ": frame skipped");
    out_obs = observationOf(failed, io.timestamp, head);
    return failed;
  };
  // A missing external file is said in one line; MRPT's loader would throw a stack dump.
  if (io.image.isExternallyStored()) {
    const std::string file = io.image.getExternalStorageFileAbsolutePath();
    std::error_code ec;
    if (!std::filesystem::is_regular_file(file, ec))
      return skipped("image file " + file + " not found");
  }
  cv::Mat image;
  try {
    io.image.forceLoad();
    image = io.image.asCvMatRef();
  } catch (const std::exception& e) {
    return skipped("the image cannot be loaded (" + std::string(e.what()).substr(0, 200) + ")");
  }
  if (image.empty()) return skipped("empty image");
  FrameResult r = st::processFrame(*head.tracker, head.frozen, image, t, in);
  if (io.image.isExternallyStored()) io.image.unload();
  if (r.failure == FrameFailure::kFrozenImage) {
    ++frozen_frames_;
    warn(head.label + " observation at " + formatLoopTime(t) + ": " + r.detail + ": frame skipped");
  }
  out_obs = observationOf(r, io.timestamp, head);
  return r;
}

CObservationStarTracker::Ptr Navigator::observationOf(const FrameResult& r,
                                                      mrpt::Clock::time_point t,
                                                      const Head& head) const {
  return observationFromFrame(r, t, head.fix_label, head.mount);
}

void Navigator::onStep(const FusionStep& fs) {
  const auto it = held_.find(fs.tag);
  ST_ASSERT(it != held_.end());
  const mrpt::obs::CObservation::Ptr obs = it->second;
  if (fs.is_frame) {
    finishPending();
    NavStep s;
    s.stamp = obs->timestamp;
    s.t = fs.t;
    s.has_frame = true;
    const FrameResult& r = *fs.frame;
    copyFrame(r, s);
    s.reason = r.detail;
    if (r.rate) {
      s.has_fix_rate = true;
      s.fix_rate = r.rate->rate_body;
      s.fix_rate_cov = r.rate->cov_body;
    }
    s.use = fs.use;
    s.reinitialized = fs.use == FixUse::kInitialized || fs.use == FixUse::kReinitialized;
    if (fs.use == FixUse::kAccepted || fs.use == FixUse::kRejected) {
      s.innovation = fs.update.innovation;
      s.innovation_cov = fs.update.innovation_cov;
      s.nis = fs.update.nis;
      s.nis_dof = fs.update.dof;
      if (!fs.update.accepted && !fs.update.reason.empty())
        s.reason += (s.reason.empty() ? "" : "; ") + fs.update.reason;
    }
    fillFilterState(s, fs.filter);
    // One observation per head, in the heads' order (the truth's head index); a head
    // without a frame at this time has none.
    pending_obs_.assign(heads_.size(), nullptr);
    if (heads_.size() > 1) s.heads.resize(heads_.size());
    for (std::size_t h = 0; h < s.heads.size(); ++h) s.heads[h].label = heads_[h].label;
    for (const HeadFrame& hf : fs.heads) {
      s.frame_time_s += hf.frame->timings.total;
      const std::size_t h = static_cast<std::size_t>(hf.head);
      if (source_ == Source::kCameraFrames) {
        pending_obs_[h] = frame_obs_[hf.tag];
        frame_obs_.erase(hf.tag);
      } else {
        pending_obs_[h] = std::dynamic_pointer_cast<CObservationStarTracker>(held_.at(hf.tag));
      }
      if (h < s.heads.size()) {
        s.heads[h].R_body_cam = hf.frame->R_body_cam;
        copyFrame(*hf.frame, s.heads[h]);
      }
      held_.erase(hf.tag);
      head_of_.erase(hf.tag);
    }
    s.heads_merged = fs.heads_merged;
    s.heads_chi2 = fs.heads_chi2;
    s.heads_dof = fs.heads_dof;
    pending_ = std::move(s);
    return;
  }
  held_.erase(it);
  // A truth marker: joins the frame step of the same time, or is a step of its own.
  if (!pending_ || pending_->stamp != obs->timestamp) {
    finishPending();
    NavStep s;
    s.stamp = obs->timestamp;
    s.t = fs.t;
    fillFilterState(s, fs.filter);
    pending_ = std::move(s);
    pending_obs_.clear();
  }
  scoreTruth(*pending_, static_cast<const mrpt::obs::CObservation6DFeatures&>(*obs), pending_obs_);
  finishPending();
}

void Navigator::finishPending() {
  if (!pending_) return;
  // The callback's observations: the heads that had a frame, in the heads' order.
  std::vector<CObservationStarTracker::Ptr> obs;
  for (const auto& o : pending_obs_)
    if (o) obs.push_back(o);
  if (callback_) callback_(*pending_, obs);
  if (keep_steps_) steps_.push_back(std::move(*pending_));
  pending_.reset();
  pending_obs_.clear();
}

}  // namespace st

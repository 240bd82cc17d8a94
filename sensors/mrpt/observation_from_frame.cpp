#include "sensors/mrpt/observation_from_frame.hpp"

namespace st {

TrackerOptions PipelineOptions::trackerOptions() const {
  TrackerOptions o = tracker;
  const auto& R = sensor_pose.getRotationMatrix();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) o.R_body_cam(r, c) = R(r, c);
  return o;
}

CObservationStarTracker::Ptr observationFromFrame(const FrameResult& frame,
                                                  mrpt::Clock::time_point t,
                                                  const std::string& sensor_label,
                                                  const mrpt::poses::CPose3D& sensor_pose) {
  auto out = CObservationStarTracker::Create();
  out->timestamp = t;
  out->sensorLabel = sensor_label;
  out->sensor_pose = sensor_pose;
  out->mode = frame.mode;
  out->failure = frame.failure;
  out->reason = frame.detail;
  if (frame.hasAttitude()) {
    out->q_ib = frame.q_ib;
    out->cov_body = frame.cov_body;
  }
  out->stars = frame.stars;
  out->num_blobs = frame.num_blobs;
  out->timings = frame.timings;
  out->rate = frame.rate;
  return out;
}

FrameResult frameFromObservation(const CObservationStarTracker& o) {
  FrameResult r;
  r.mode = o.mode;
  r.failure = o.failure;
  r.detail = o.reason;
  r.q_ib = o.q_ib;
  r.cov_body = o.cov_body;
  r.stars = o.stars;
  const auto& R = o.sensor_pose.getRotationMatrix();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r.R_body_cam(i, j) = R(i, j);
  r.num_blobs = o.num_blobs;
  r.timings = o.timings;
  r.rate = o.rate;
  return r;
}

}  // namespace st

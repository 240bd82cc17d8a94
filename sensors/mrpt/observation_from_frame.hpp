/// @file observation_from_frame.hpp
/// The MRPT edge of the tracking stage: a FrameResult (sensors/tracking/frame.hpp) as a
/// CObservationStarTracker, and the MRPT-side options of a star tracker.
#pragma once
#include <mrpt/core/Clock.h>
#include <mrpt/poses/CPose3D.h>

#include <string>

#include "sensors/mrpt/observation_star_tracker.hpp"
#include "sensors/tracking/frame.hpp"
#include "sensors/tracking/tracker_options.hpp"

namespace st {

/// A star tracker as MRPT sees it: the tracker's options, the label of its observations and
/// the camera's pose on the vehicle. The pose's rotation is the tracker's mounting
/// (trackerOptions() sets TrackerOptions::R_body_cam from it; `tracker.R_body_cam` itself is
/// not used), its translation is only recorded (stars are at infinity).
struct PipelineOptions {
  std::string sensor_label = "STAR_TRACKER";
  mrpt::poses::CPose3D sensor_pose;
  TrackerOptions tracker;

  TrackerOptions trackerOptions() const;
};

/// The observation of one frame: `t` is the frame's timestamp.
/// The inverse: a recorded fix (e.g. a live sensor's) as the FrameResult the fusion loop takes.
FrameResult frameFromObservation(const CObservationStarTracker& o);

CObservationStarTracker::Ptr observationFromFrame(const FrameResult& frame,
                                                  mrpt::Clock::time_point t,
                                                  const std::string& sensor_label,
                                                  const mrpt::poses::CPose3D& sensor_pose);

}  // namespace st

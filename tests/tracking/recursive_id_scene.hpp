// The recursive-identification tests' common scene: one simulated frame of a rich field
// (Orion) held still, the options matching the simulated sensor, and a prediction at a given
// attitude with a round covariance.
#pragma once
#include "common/conventions.hpp"
#include "sensors/identify/recursive_id.hpp"
#include "sensors/sim/motion.hpp"
#include "tests/tracking/tracker_sim.hpp"

namespace st::test::recursive_id {

inline RecursiveIdOptions options() {
  const TrackerOptions t = test::simTrackerOptions();
  RecursiveIdOptions o;
  o.detect = t.detect;
  o.exposure_s = t.exposure_s;
  return o;
}

struct Scene {
  test::FrameSimulator::Frame frame;
  Quat q_ic;
};

inline Scene scene() {
  const HoldMotion hold(attitudeFromRaDecRoll({deg2rad(83.0), deg2rad(-1.0), deg2rad(20.0)}));
  test::FrameSimulator sim(11);
  Scene s;
  s.frame = sim.frame(hold, 0.0);
  s.q_ic = s.frame.q_ib;  // camera = body
  return s;
}

}  // namespace st::test::recursive_id

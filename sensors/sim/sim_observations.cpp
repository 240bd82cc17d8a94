#include "sensors/sim/sim_observations.hpp"

namespace st {

mrpt::obs::CObservation6DFeatures::Ptr makeTruthObservation(const Quat& q_ib,
                                                            const std::vector<TrueStar>& stars,
                                                            mrpt::Clock::time_point t,
                                                            const std::string& label) {
  FrameTruth truth;
  truth.q_ib = q_ib;
  truth.stars.reserve(stars.size());
  for (const TrueStar& s : stars) truth.stars.push_back({s.id, s.px, s.mag});
  return makeTruthObservation(truth, t, label);
}

}  // namespace st

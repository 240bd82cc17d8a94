/// @file sim_observations.hpp
/// The simulator's frames as observations of the rawlog contract
/// (sensors/mrpt/rawlog_contract.hpp, which holds the labels, encoders and decoders).
#pragma once
#include <vector>

#include "sensors/mrpt/rawlog_contract.hpp"
#include "sensors/sim/star_renderer.hpp"

namespace st {

/// GROUND_TRUTH of a rendered frame (the renderer's true stars; their electrons are not
/// part of the contract).
mrpt::obs::CObservation6DFeatures::Ptr makeTruthObservation(
    const Quat& q_ib, const std::vector<TrueStar>& stars, mrpt::Clock::time_point t,
    const std::string& label = kGroundTruthLabel);

}  // namespace st

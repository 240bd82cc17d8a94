/// @file experiments.hpp
/// Factories of the experiments, one per file (registered in experiment_registry.cpp).
#pragma once
#include <memory>

#include "app/montecarlo/experiment.hpp"

namespace st::app::mc {

std::unique_ptr<Experiment> makeStarCount();
std::unique_ptr<Experiment> makeFovSelection();
std::unique_ptr<Experiment> makeLisRobustness();
std::unique_ptr<Experiment> makeErrorVsStars();
std::unique_ptr<Experiment> makeTiming();
std::unique_ptr<Experiment> makeCentroidDefocus();
std::unique_ptr<Experiment> makeFewStars();
std::unique_ptr<Experiment> makeMagnitudeError();
std::unique_ptr<Experiment> makeNearField();

}  // namespace st::app::mc

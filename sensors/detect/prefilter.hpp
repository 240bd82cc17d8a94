/// @file prefilter.hpp
/// Pre-filters of seed 004 §4.1 / §4.2.2 that remove isolated noise pixels from the
/// thresholded mask before blobs are formed. Worth it at low thresholds (k ~ 1-2), where
/// noise alone puts many pixels above the threshold but rarely 9 of 25 close together.
#pragma once
#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace st {

/// `mask`: CV_8UC1, 0 or 255, modified in place. `name`: "none", "neighbourhood" (5x5 count
/// centred on each candidate, starCentroid2) or "grid" (5x5 cells on a fixed grid, a cell
/// and its 8 neighbours kept when it passes, starCentroid3). Returns false for an unknown name.
bool applyPrefilter(cv::Mat& mask, const std::string& name, int min_count);

std::vector<std::string> prefilterNames();

}  // namespace st

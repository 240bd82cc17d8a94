/// @file star_match.hpp
/// One identified star: which observation is which catalog star, and how well they agree.
#pragma once
#include <cstdint>

namespace st {

struct StarMatch {
  uint32_t obs_index = 0;   ///< index into the observation list
  uint32_t star_index = 0;  ///< index into StarDatabase::stars()
  uint32_t catalog_id = 0;  ///< HIP (or HR) number
  double residual = 0;      ///< [rad] angle between observed and predicted direction
  double residual_px = 0;   ///< [px] distance between centroid and predicted pixel
};

}  // namespace st

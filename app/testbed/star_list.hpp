/// @file star_list.hpp
/// The star list `testbed draw` writes beside its screen image and `testbed solve` reads as
/// the display database: one CSV line per drawn star, brightest first, after a comment line
/// with the sky attitude of the testbed frame.
///   # startracker testbed star list; attitude_ypr_deg = Y P R
///   id,screen_x_px,screen_y_px,mag,ra_deg,dec_deg
#pragma once
#include <string>
#include <vector>

#include "sensors/testbed/display_image.hpp"

namespace st::app {

struct DisplayStarList {
  Vec3 attitude_ypr_deg = Vec3::Zero();  ///< the testbed frame's attitude in the sky
  std::vector<testbed::DisplayStar> stars;
};

void writeStarList(const std::string& path, const DisplayStarList& list);
/// InputError naming the file and line on a malformed list.
DisplayStarList readStarList(const std::string& path);

}  // namespace st::app

/// @file star_list.hpp
/// A star list instead of an image (solve-field's habit): the detections are given, so
/// detection is skipped.
///  - CSV: a header line naming the columns x, y and optionally flux (any order, any case;
///    other columns ignored), one star per line; pixels 0-based as in the rest of the
///    project (conventions.hpp: the centre of the first pixel is 0,0).
///  - FITS binary table (solve-field's xylist, .xyls/.axy/.fits): columns X, Y and
///    optionally FLUX in the first table HDU; pixels 1-based (FITS), converted to 0-based.
///    IMAGEW / IMAGEH and DATE-OBS in its header give the image size and the epoch.
/// Stars are sorted brightest first by flux (the file's order when there is no flux).
#pragma once
#include <optional>
#include <string>
#include <vector>

#include "sensors/detect/centroid.hpp"

namespace st::solve {

struct StarList {
  std::vector<Centroid> stars;
  int width = 0, height = 0;          ///< from the FITS header (IMAGEW/IMAGEH), else 0
  std::optional<double> epoch_jyear;  ///< FITS DATE-OBS or a timestamp in the file name
  std::string epoch_source;
};

/// True when `path` names a star list: .csv, .xyls or .axy, or a FITS file whose primary
/// HDU holds no image and whose next HDU is a binary table.
bool isStarList(const std::string& path);

/// Throws InputError naming the file (and the line or column) on a bad list.
StarList loadStarList(const std::string& path);

}  // namespace st::solve

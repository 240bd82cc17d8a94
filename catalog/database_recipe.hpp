/// @file database_recipe.hpp
/// The one recipe of the star database a camera needs, shared by `solve`, `replay`, `live`
/// and CStarTrackerSensor, so that they identify against the same stars for the same camera:
///  - pairs up to the image diagonal + 0.2 deg (every pair of stars in one image);
///  - unresolved doubles merged below 1.5 px (seed 004 eq. 6.1/6.2: one image peak);
///  - the neighbour table out to half the diagonal (seed 002 recursive ID, Liebe's features);
///  - proper motion, parallax and (optionally) annual aberration to the observation epoch.
/// `catalog build` exposes every parameter; the simulator and the Monte Carlo experiments
/// build their own (a renderer needs no pairs; the papers' experiments fix their own).
#pragma once
#include <string>

#include "catalog/star_database.hpp"

namespace st {

/// Stars closer than this many pixels are one image peak (seed 004 eq. 6.1/6.2): the one rule
/// of the double-star merge, from the optics (the recipe, and `catalog build`'s default).
constexpr double kUnresolvedDoubleSepPx = 1.5;

struct CameraDatabaseRecipe {
  double diagonal_fov_rad = 0;  ///< the camera's full diagonal field of view
  double pixel_scale_rad = 0;   ///< [rad/px] the finest pixel scale
  double mag_limit = 6.5;
  double epoch_jyear = 0;       ///< observation epoch (Julian year)
  bool aberration = true;
};

/// The database parameters of the recipe (InputError for a non-positive FOV or scale).
DatabaseParams databaseParams(const CameraDatabaseRecipe& r);

/// Empty when a database built with `p` pairs every two stars of an image whose diagonal FOV
/// is `diagonal_fov_rad`; else a one-line warning naming `db_path`, both angles and the
/// `catalog build` options that would cover the image (`--diagonal-fov-deg`; `--fov-deg` is
/// the horizontal FOV there as everywhere).
std::string pairCoverageWarning(const DatabaseParams& p, double diagonal_fov_rad,
                                const std::string& db_path);

}  // namespace st

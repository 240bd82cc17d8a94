/// @file database_cache.hpp
/// The camera (or FOV search) of a solve and the in-memory database built for it, kept
/// between calls: a program that solves frame after frame of one camera builds it once.
#pragma once
#include <optional>
#include <vector>

#include "app/solve/solve_options.hpp"
#include "include/startracker/startracker.hpp"

namespace st::api {

/// The cameras to try: one (camera file / FOV) or a grid of horizontal FOVs (as `solve`).
struct SearchPlan {
  std::optional<CameraModel> fixed;
  bool fit_focal = true;  ///< a FOV without a camera file is approximate: fit the focal length
  std::vector<double> grid;
  double scale_tol = 0.02;
  double max_diag = 0;       ///< [rad] the widest image diagonal of the search
  double pixel_scale = 0;    ///< [rad/px] the finest pixel scale of the search
};

SearchPlan searchPlan(const app::SolveOptions& o, int width, int height);

/// The recipe's database (catalog/database_recipe.hpp, annual aberration applied) from the
/// default catalog.
Database buildDatabase(double max_diag, double pixel_scale, double mag_limit, double epoch_jyear);

/// The database of the recipe for `plan` at `epoch_jyear`: the one built last for the same
/// diagonal, pixel scale and limit when its stars have moved by less than solve's tolerance
/// (app/solve/solve_epoch.hpp) since, else a new one. Thread-safe.
Database cachedDatabase(const SearchPlan& plan, double mag_limit, double epoch_jyear);

}  // namespace st::api

/// @file identify_frame.hpp
/// solve's identification step, shared by `startracker solve` (solve_run.cpp) and the
/// library's solve (api/solve.cpp): the identifier and solver of the options, the centroid
/// floor, the position hint and time limit, and the camera search (a camera file healed, an
/// approximate FOV refined, or a grid of FOVs) over both parities.
#pragma once
#include <chrono>
#include <optional>
#include <string>
#include <vector>

#include "solve/solve_options.hpp"
#include "sensors/identify/plate_solve.hpp"

namespace st::solve {

/// The cameras to try: one (a camera file or a FOV) or a grid of horizontal FOVs.
struct CameraChoice {
  const std::optional<CameraModel>& fixed;
  bool fit_focal;  ///< a FOV without a camera file is approximate: fit the focal length
  const std::vector<double>& grid;
  double scale_tol;
  double pixel_aspect;  ///< of the grid's cameras
};

PlateSolveResult identifyFrame(const SolveOptions& o, const std::vector<Centroid>& stars,
                               int width, int height, const StarDatabase& db,
                               const CameraChoice& cameras,
                               const std::optional<PositionHint>& hint, ParityChoice parity,
                               std::chrono::steady_clock::time_point t_start);

}  // namespace st::solve

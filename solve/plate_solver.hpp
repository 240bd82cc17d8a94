/// @file plate_solver.hpp
/// Plate solving as a stage: one frame (an image file, a star list, or an image in memory)
/// -> centroids -> identification over the camera or FOV search, both parities, within a
/// hint and a time limit -> attitude with covariance, in the celestial frame asked for.
/// `startracker solve` (app/), st::api::solve (api/) and Python's startracker.solve call this
/// and print its JSON (solve_output.hpp), so the three give one answer.
///
///   solve::SolveOptions o;  o.camera.fov_deg = 11.4;
///   solve::PlateSolver solver(o);                  // loads --database, reads --dark once
///   auto f = solver.solveFile("frame.png");        // throws InputError on bad input
///   std::cout << outcomeJson(*f).dump();
#pragma once
#include <chrono>
#include <atomic>
#include <memory>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>

#include "solve/celestial_frame.hpp"
#include "catalog/database_cache.hpp"
#include "solve/frame_input.hpp"
#include "solve/solve_options.hpp"
#include "solve/solve_output.hpp"

namespace st::solve {

/// A frame's code: what the command exits with for it.
constexpr int kSolved = 0, kNotSolved = 1, kBadInput = 2;

/// A frame's result, kept until it is printed (a batch prints in input order).
struct FrameOutcome {
  SolveOptions o;  ///< the solver's options, input = this frame
  FrameInput in;
  std::shared_ptr<const StarDatabase> db;  ///< keeps the database alive
  std::unique_ptr<SolveReport> rep;        ///< null when an error ended the frame
  int code = kSolved;                      ///< kSolved, kNotSolved or kBadInput
  std::string error;                       ///< the error that ended the frame
  double ms = 0;                           ///< wall time of the frame
};

/// The one JSON object of a frame: solutionJson, failureJson, or errorJson with "image".
nlohmann::ordered_json outcomeJson(const FrameOutcome& f);

struct CameraSearch;    // plate_solver.cpp: the cameras a frame tries
struct DatabaseChoice;  // plate_solver.cpp: its database, where from, at which epoch
struct Prepared;        // plate_solver.cpp: both, chosen from an image's header

class PlateSolver {
 public:
  /// Throws InputError for a bad option, an unreadable --database or --dark. Databases built
  /// for a camera are the process's (cameraDatabase, catalog/database_cache.hpp): solvers of
  /// one process share them.
  explicit PlateSolver(SolveOptions options);
  /// The same with a database the caller loaded or built (`source` says where from;
  /// `from_file` true checks the observation epoch against it as --database does).
  PlateSolver(SolveOptions options, std::shared_ptr<const StarDatabase> db, std::string source,
              bool from_file);

  /// An image file or a star list. Throws InputError (bad input) or std::exception.
  std::unique_ptr<FrameOutcome> solveFile(const std::string& path) const;
  /// solveFile with every exception turned into the outcome's code and error (a batch goes on).
  std::unique_ptr<FrameOutcome> solveFileCaught(const std::string& path) const;
  /// An 8- or 16-bit grey image in memory (not copied; it must stay valid during the call),
  /// named `name` in the result; the epoch is the options' (else the database's, else today).
  std::unique_ptr<FrameOutcome> solveImage(const cv::Mat& image, const std::string& name) const;

  const SolveOptions& options() const { return o_; }

 private:
  std::unique_ptr<FrameOutcome> solveInput(FrameInput in, const std::string& name,
                                           std::chrono::steady_clock::time_point t_start,
                                           const Prepared* early = nullptr) const;
  DatabaseChoice database(const SolveOptions& o, const CameraSearch& cs, int width, int height,
                          const std::optional<double>& epoch_jyear,
                          const std::string& epoch_source,
                          std::chrono::steady_clock::time_point t_start) const;
  SolveOptions o_;
  std::shared_ptr<const StarDatabase> given_db_;  ///< --database, or the caller's
  std::string given_source_;
  bool given_from_file_ = false;
  double given_ms_ = 0;
  /// The --database load is counted in the first frame's timing only (a batch pays it once).
  std::shared_ptr<std::atomic<bool>> given_counted_ = std::make_shared<std::atomic<bool>>(false);
  CelestialFrame frame_;  ///< the frame asked for
  double pixel_aspect_ = 1;  ///< the camera's fx / fy, for detection
};

}  // namespace st::solve

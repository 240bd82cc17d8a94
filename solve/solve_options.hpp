/// @file solve_options.hpp
/// The options of `startracker solve` and the one entry that runs it. The command is split
/// by concern: solve_options.cpp (flags), frame_input.* (image or star list -> centroids),
/// star_list.* (CSV / FITS table reader), solve_epoch.* (which epoch, and whether a star
/// database file fits it), solve_run.cpp (the pipeline), solve_output.* (text and JSON).
#pragma once
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "solve/camera_options.hpp"
#include "sensors/identify/identifier.hpp"
#include "sensors/identify/plate_solve.hpp"

namespace st::solve {

struct SolveOptions {
  std::vector<std::string> inputs;  ///< images, star lists and folders (input_list.hpp)
  std::string input;  ///< the frame being solved: image, or a star list (CSV x,y,flux or a FITS table X,Y,FLUX)
  CameraOptions camera;
  std::string database;
  std::string algorithm = StarIdentifier::defaultName();
  std::string solver = WahbaSolver::defaultName();
  bool json = false;
  std::vector<double> fov_range_deg = {5.0, 30.0};
  double mag_limit = 6.6;
  double epoch = 0;  ///< 0 = from the image (else the database's, else today)
  int max_stars = 12;
  double min_sigma_px = -1;  ///< <0: 0.1 px (the model-error term adds the rest)
  std::string annotate;      ///< PNG path for a labelled picture of the solved frame
  std::string parity = "both";
  double ra_deg = NAN, dec_deg = NAN, radius_deg = NAN;  ///< position hint (all or none)
  double cpulimit_s = 0;                                 ///< 0 = no limit
  int width = 0, height = 0;                             ///< image size of a star list
  int threads = 1;        ///< frames solved at once in a batch
  bool no_cache = false;  ///< build the in-memory database without the disk cache
  std::string wcs;        ///< FITS WCS header output (one frame)
  bool no_aberration = false;  ///< astrometric frame instead of apparent
  std::vector<double> observer_velocity_km_s;  ///< added to the Earth's (GCRS/ICRS axes)
  std::string dark;     ///< master dark file (`startracker dark`), subtracted before detection
  cv::Mat dark_frame;   ///< its pixels, read once by the PlateSolver
  // A batch at scale (app/solve_batch.cpp, results_file.hpp):
  std::string files_from;  ///< a list file of frames, one per line ("-": standard input)
  std::string shard;       ///< "i/N": this run solves frames i, i + N, ... of the list
  std::string output;      ///< JSON Lines results, a line appended as each frame finishes
  bool resume = false;     ///< continue `output`: frames with a line there are skipped
  bool force = false;      ///< replace existing outputs (--annotate, --wcs, -o)
  std::string option_prefix = "--";  ///< how messages name options ("" in the library)

  /// The parity flag as the search takes it.
  ParityChoice parityChoice() const;
  /// The hint when --ra/--dec/--radius are given; InputError when only some are, or a value
  /// is out of range.
  std::optional<PositionHint> positionHint() const;
};

/// The widest image diagonal [deg] solve takes: it models the lens as a pinhole, and the star
/// database of a wider field holds pairs across most of the sky (measured: 0.8 GB and over a
/// minute to build for a 114 deg diagonal).
constexpr double kMaxSolveDiagonalDeg = 120;
/// The coarsest pixel scale [deg/px] solve takes: unresolved doubles (1.5 px) are merged in
/// the star database, which merges below 1 deg.
constexpr double kMaxSolvePixelScaleDeg = 0.66;

/// InputError (exit 2) naming the flag and value (--fov-deg, --fov-range) or the camera file
/// when the field of view on a `width` x `height` image is outside what solve handles.
void requireSolvableFov(const SolveOptions& o, int width, int height);


}  // namespace st::solve

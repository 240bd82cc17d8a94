/// @file mc_options.hpp
/// Options of `startracker montecarlo`. The ones that change results are written to each
/// run's `<experiment>_run.txt` (run_file.hpp: one strict [montecarlo_run] section) so that
/// `montecarlo merge` can rebuild the report from shard files alone and refuse shards of
/// different runs.
#pragma once
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace st::app::mc {

struct McOptions {
  // --- what is computed (stored in the run file) ---
  std::string experiment;
  std::size_t runs = 1000;  ///< trials (random attitudes)
  uint64_t seed = 1;
  double fov_deg = 15.0;  ///< horizontal FOV of the simulated camera
  int width = 1024, height = 1024;
  double mag_limit = 6.0;
  std::vector<double> mags = {4.0, 4.5, 5.0, 5.5, 6.0, 6.5};  ///< star-count, fov-selection
  std::vector<double> fovs_deg;  ///< fov-selection grid (square FOV, full angle); empty = default
  std::vector<std::string> algorithms;  ///< identification algorithms; empty = experiment default
  std::vector<std::string> solvers;     ///< Wahba solvers; empty = all
  double noise_px = 0.1;                ///< centroid noise 1-sigma per axis (baseline)
  double merge_arcsec = 60.0;           ///< database double-star merge distance
  std::string catalog;                  ///< catalog file; empty = the committed Hipparcos subset
  /// [deg] circular field stop (full angle) inside the image: stars farther than half of it
  /// from the boresight are not seen (seed 003's 30 deg "opening angle"); 0 = the image.
  double field_stop_deg = 0;
  /// Identical camera heads, boresights 90 deg apart (fov-selection: seed 002 Fig. 11's
  /// "two identical star trackers"); the star counts of all heads add up.
  int heads = 1;

  // --- how it is run (not stored) ---
  int threads = 1;
  int shard_index = 0, shard_count = 1;
  std::string out_dir = "montecarlo-out";
  bool plots = true;
  std::string gnuplot;  ///< gnuplot program override
  bool progress = true;

  /// The stored options as key = value strings (lists comma-separated, numbers %.17g).
  std::map<std::string, std::string> toKeyValues() const;
  /// Inverse of toKeyValues (run options are left at their defaults). InputError naming
  /// `source` and the key on a missing or malformed value.
  static McOptions fromKeyValues(const std::map<std::string, std::string>& kv,
                                 const std::string& source);
  /// The command line that reproduces the stored options (for reports).
  std::string commandLine() const;
};

/// Parses "i/N" (0 <= i < N); InputError naming the value otherwise.
void parseShard(const std::string& text, int& index, int& count);

/// Number formatting shared by every table: %.*g with `digits` significant digits.
std::string fmt(double v, int digits = 9);
std::string joinList(const std::vector<double>& v);
std::string joinList(const std::vector<std::string>& v);

}  // namespace st::app::mc

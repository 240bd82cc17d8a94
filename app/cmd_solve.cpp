// `startracker solve`: its flags (CLI11) into the plate solver's options (solve/), the batch
// run in app/solve/solve_batch.cpp.
#include <memory>
#include <string>
#include <vector>

#include "app/cli/common_flags.hpp"
#include "app/camera_flags.hpp"
#include "app/cli/validators.hpp"
#include "app/command.hpp"
#include "sensors/attitude/wahba.hpp"
#include "sensors/identify/identifier.hpp"
#include "solve/solve_options.hpp"

namespace st::app {

int runSolve(const solve::SolveOptions& o);
int runSolveMerge(const solve::SolveOptions& o, const std::vector<std::string>& other_flags);

namespace {
void addSearchOptions(CLI::App& cmd, solve::SolveOptions& o) {
  cmd.add_option("--parity", o.parity,
                 "Image parity: normal, flipped (mirrored left-right, e.g. a bottom-up FITS), "
                 "or both (normal first, flipped only when normal fails)")
      ->check(CLI::IsMember({"normal", "flipped", "both"}))
      ->capture_default_str();
  cmd.add_option("--ra", o.ra_deg, "Position hint: RA of the boresight [deg] (with --dec, --radius)");
  cmd.add_option("--dec", o.dec_deg, "Position hint: Dec of the boresight [deg]");
  cmd.add_option("--radius", o.radius_deg,
                 "Position hint: accept only a boresight within this radius [deg]");
  cmd.add_option("--cpulimit", o.cpulimit_s,
                 "Give up after this many seconds of the frame (checked inside identification and "
                 "a database build; decoding and detection run to their end)")
      ->check(CLI::PositiveNumber);
  cmd.add_option("--width", o.width, "Image width [px] of a star list (CSV or FITS table)")
      ->check(CLI::Range(1, 1000000));
  cmd.add_option("--height", o.height, "Image height [px] of a star list")
      ->check(CLI::Range(1, 1000000));
}

/// A batch at scale: a file list, one shard of it, results that survive a kill.
void addBatchOptions(CLI::App& cmd, solve::SolveOptions& o) {
  cmd.add_option("--files-from", o.files_from,
                 "A text file listing frames, one path per line ('#' comments; '-': standard "
                 "input), solved after the IMAGE arguments");
  cmd.add_option("--shard", o.shard,
                 "i/N: solve frames i, i + N, i + 2N, ... of the list (0 <= i < N), one part of "
                 "a split run (e.g. $SLURM_ARRAY_TASK_ID/$SLURM_ARRAY_TASK_COUNT)");
  cmd.add_option("-o,--output", o.output,
                 "JSON Lines results file: one line per frame (the --json object), appended as "
                 "each frame finishes, so a killed run keeps what it did. With it the exit code "
                 "is the run's: 0 when every frame has its line, solved or not. An existing "
                 "file is refused unless --resume (or -f). `solve merge PART... -o OUT [--files-from "
                 "LIST]` joins the parts of a sharded run, in the list's order");
  cli::addForceFlag(cmd, o.force,
               "Replace existing output files: --annotate, --wcs, -o (without it an existing "
               "output is refused; -o is continued by --resume instead)");
  cmd.add_flag("--resume", o.resume,
               "Continue the -o file of an interrupted run: frames with a line there are "
               "skipped, a last line cut by the interruption is solved again");
}
}  // namespace

void addSolveCommand(CLI::App& root, CommandRun& run_fn) {
  auto* cmd = root.add_subcommand(
      "solve", "Lost-in-space: detect, identify and solve the attitude of one image");
  auto o = std::make_shared<solve::SolveOptions>();
  cmd->add_option("IMAGE", o->inputs,
                  "PNG, JPEG, TIFF (8/16-bit) or FITS image; or a star list instead of an "
                  "image: CSV with a header line and columns x,y[,flux] (pixels, 0-based), or "
                  "a FITS table with columns X, Y[, FLUX] (1-based, as solve-field's xylist). "
                  "Several, and folders (their images, sorted by name), make a batch. "
                  "`solve merge PART...` joins the -o files of a sharded run");
  addCameraFlags(*cmd, o->camera);
  cmd->add_option("--database", o->database,
                  "Star database from `startracker catalog build` (default: build one in memory "
                  "from the committed Hipparcos subset)");
  std::string algo_help = "Identification algorithm:\n" + StarIdentifier::help();
  cmd->add_option("--algorithm", o->algorithm, algo_help)
      ->check(CLI::IsMember(StarIdentifier::names()))
      ->capture_default_str();
  cmd->add_option("--solver", o->solver, "Wahba solver")
      ->check(CLI::IsMember(WahbaSolver::names()))
      ->capture_default_str();
  cmd->add_flag("--json", o->json,
                "Print one JSON object per frame, one per line (also for an error)");
  cmd->add_option("--threads", o->threads, "Frames solved at once in a batch")
      ->check(CLI::Range(1, 256))
      ->capture_default_str();
  cmd->add_flag("--no-cache", o->no_cache,
                "Do not keep the in-memory database in the user's cache folder "
                "($XDG_CACHE_HOME/startracker or ~/.cache/startracker)");
  cmd->add_option("--wcs", o->wcs,
                  "Write a FITS WCS header (TAN, SIP terms for a camera file's distortion) of "
                  "the solved frame");
  cmd->add_flag("--no-aberration", o->no_aberration,
                "Astrometric (catalog, ICRS) frame, as astrometry.net and FITS WCS; default: "
                "apparent, with the Earth's annual aberration");
  cmd->add_option("--observer-velocity-km-s", o->observer_velocity_km_s,
                  "Observer's velocity w.r.t. the Earth's centre [km/s], GCRS/ICRS axes, added "
                  "to the annual aberration (a spacecraft's orbit)")
      ->expected(3);
  cmd->add_option("--annotate", o->annotate,
                  "Write a labelled PNG of the frame: blobs marked star / radiation hit / "
                  "diffuse / rejected, identified stars named, the solution or why it failed");
  cmd->add_option("--fov-range", o->fov_range_deg,
                  "Horizontal FOV range [deg] searched when neither --camera nor --fov-deg")
      ->expected(2)
      ->capture_default_str();
  cmd->add_option("--mag-limit", o->mag_limit, "V limit of the in-memory database")
      ->capture_default_str();
  cmd->add_option("--epoch", o->epoch,
                  "Observation epoch [Julian year] (default: from FITS DATE-OBS or the file "
                  "name, else the --database's epoch, else today)")
      ->check(cli::Number(1000, 3000));  // a typo (0, -1, 999) is refused, not ignored
  cmd->add_option("--max-stars", o->max_stars, "Brightest stars used to form patterns")
      ->check(CLI::Range(4, 100))
      ->capture_default_str();
  cmd->add_option("--min-sigma-px", o->min_sigma_px,
                  "Floor of the centroid 1-sigma [px] (default 0.1, at most 2); the camera "
                  "model's own error is measured on the stars and added")
      ->check(cli::Number(0, kMaxCentroidSigmaFloorPx, cli::Bound::kOpen));
  cmd->add_option("--dark", o->dark,
                  "Master dark (`startracker dark`; FITS, PNG or TIFF, the images' size and "
                  "depth), subtracted before detection");
  addSearchOptions(*cmd, *o);
  addBatchOptions(*cmd, *o);
  cmd->callback([o, cmd, &run_fn] {
    if (o->inputs.empty() || o->inputs.front() != "merge") {
      run_fn = [o] { return runSolve(*o); };
      return;
    }
    // `solve merge PART...`: the flags that solve frames mean nothing there; refuse them
    // rather than let a user believe they applied.
    std::vector<std::string> other_flags;
    for (const CLI::Option* opt : cmd->get_options()) {
      const std::string name = opt->get_name();
      if (opt->count() > 0 && !opt->get_positional() && name != "--output" && name != "--force" &&
          name != "--files-from" && name != "--verbose" && name != "--quiet")
        other_flags.push_back(name);
    }
    run_fn = [o, other_flags] { return runSolveMerge(*o, other_flags); };
  });
}

}  // namespace st::app

// `startracker solve`'s flags (CLI11) and their checks.
#include "app/solve/solve_options.hpp"

#include <cstdio>
#include <memory>

#include "app/command.hpp"
#include "common/conventions.hpp"
#include "common/errors.hpp"
#include "sensors/attitude/wahba.hpp"

namespace st::app {

ParityChoice SolveOptions::parityChoice() const {
  if (parity == "normal") return ParityChoice::Normal;
  if (parity == "flipped") return ParityChoice::Flipped;
  return ParityChoice::Both;
}

std::optional<PositionHint> SolveOptions::positionHint() const {
  const int given = int(!std::isnan(ra_deg)) + int(!std::isnan(dec_deg)) + int(!std::isnan(radius_deg));
  if (given == 0) return std::nullopt;
  if (given != 3)
    throw InputError("--ra, --dec and --radius go together: the hint is a circle on the sky");
  if (!(ra_deg >= 0 && ra_deg <= 360))
    throw InputError("--ra " + std::to_string(ra_deg) + ": must be in [0, 360] deg");
  if (!(dec_deg >= -90 && dec_deg <= 90))
    throw InputError("--dec " + std::to_string(dec_deg) + ": must be in [-90, 90] deg");
  if (!(radius_deg > 0 && radius_deg <= 180))
    throw InputError("--radius " + std::to_string(radius_deg) + ": must be in (0, 180] deg");
  return PositionHint{deg2rad(ra_deg), deg2rad(dec_deg), deg2rad(radius_deg)};
}

namespace {
void checkFov(const std::string& what, const CameraModel& widest, const CameraModel& finest) {
  char b[400];
  const double diag = rad2deg(2 * widest.halfDiagonalFov());
  if (!(diag <= kMaxSolveDiagonalDeg)) {
    std::snprintf(b, sizeof b,
                  "%s: a %dx%d image with a %.1f deg horizontal field of view has a %.1f deg "
                  "diagonal; solve takes fields up to a %.0f deg diagonal (a pinhole lens model; "
                  "fisheye and all-sky images are not supported)",
                  what.c_str(), widest.width(), widest.height(), rad2deg(widest.horizontalFov()),
                  diag, kMaxSolveDiagonalDeg);
    throw InputError(b);
  }
  const double scale = rad2deg(finest.pixelScale());
  if (!(scale <= kMaxSolvePixelScaleDeg)) {
    std::snprintf(b, sizeof b,
                  "%s: a %dx%d image with a %.1f deg horizontal field of view has %.2f deg "
                  "pixels; solve takes pixels up to %.2f deg (a larger image, or a narrower field)",
                  what.c_str(), finest.width(), finest.height(), rad2deg(finest.horizontalFov()),
                  scale, kMaxSolvePixelScaleDeg);
    throw InputError(b);
  }
}

std::string num(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%g", v);
  return b;
}
}  // namespace

void requireSolvableFov(const SolveOptions& o, int w, int h) {
  if (o.camera.given()) {
    const CameraModel cam = o.camera.resolve(w, h);
    checkFov(o.camera.camera_file.empty() ? "--fov-deg " + num(o.camera.fov_deg)
                                          : o.camera.camera_file,
             cam, cam);
    return;
  }
  const auto& r = o.fov_range_deg;
  if (r.size() != 2 || !(r[0] > 0) || !(r[1] >= r[0])) return;  // cameraSearch says why
  checkFov("--fov-range " + num(r[0]) + " " + num(r[1]), CameraModel::fromFov(w, h, deg2rad(r[1])),
           CameraModel::fromFov(w, h, deg2rad(r[0])));
}

namespace {
void addSearchOptions(CLI::App& cmd, SolveOptions& o) {
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
                 "Give up after this many seconds (checked between FOV and parity tries)")
      ->check(CLI::PositiveNumber);
  cmd.add_option("--width", o.width, "Image width [px] of a star list (CSV or FITS table)")
      ->check(CLI::Range(1, 1000000));
  cmd.add_option("--height", o.height, "Image height [px] of a star list")
      ->check(CLI::Range(1, 1000000));
}
}  // namespace

void addSolveCommand(CLI::App& root, CommandRun& run_fn) {
  auto* cmd = root.add_subcommand(
      "solve", "Lost-in-space: detect, identify and solve the attitude of one image");
  auto o = std::make_shared<SolveOptions>();
  cmd->add_option("IMAGE", o->inputs,
                  "PNG, JPEG, TIFF (8/16-bit) or FITS image; or a star list instead of an "
                  "image: CSV with a header line and columns x,y[,flux] (pixels, 0-based), or "
                  "a FITS table with columns X, Y[, FLUX] (1-based, as solve-field's xylist). "
                  "Several, and folders (their images, sorted by name), make a batch")
      ->required();
  o->camera.addTo(*cmd);
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
                  "Write a labelled PNG of the solved frame (blobs circled, stars named)");
  cmd->add_option("--fov-range", o->fov_range_deg,
                  "Horizontal FOV range [deg] searched when neither --camera nor --fov-deg")
      ->expected(2)
      ->capture_default_str();
  cmd->add_option("--mag-limit", o->mag_limit, "V limit of the in-memory database")
      ->capture_default_str();
  cmd->add_option("--epoch", o->epoch,
                  "Observation epoch [Julian year] (default: from FITS DATE-OBS or the file "
                  "name, else the --database's epoch, else today)");
  cmd->add_option("--max-stars", o->max_stars, "Brightest stars used to form patterns")
      ->check(CLI::Range(4, 100))
      ->capture_default_str();
  cmd->add_option("--min-sigma-px", o->min_sigma_px,
                  "Floor of the centroid 1-sigma [px] (default 0.1); the camera model's own "
                  "error is measured on the stars and added");
  cmd->add_option("--dark", o->dark,
                  "Master dark (`startracker dark`; FITS, PNG or TIFF, the images' size and "
                  "depth), subtracted before detection");
  addSearchOptions(*cmd, *o);
  cmd->callback([o, &run_fn] { run_fn = [o] { return runSolve(*o); }; });
}

}  // namespace st::app

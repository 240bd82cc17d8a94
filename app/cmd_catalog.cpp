// `startracker catalog build|info`: the ground program. Builds the star database (pairs +
// k-vector, cone index, neighbour table) from a real catalog for a camera and magnitude
// limit, and prints what a database file holds.
//
// The camera: `--fov-deg` is the HORIZONTAL field of view here as in every other command
// (solve, camera, scenario files), with `--size W H` for the aspect; without it the image is
// taken as square, which covers every landscape sensor of that horizontal FOV. Until issue 21
// `catalog build --fov-deg` meant the diagonal: such a call now builds pairs out to a wider
// angle (a superset, never fewer pairs) and says so on stderr; `--diagonal-fov-deg` keeps the
// old meaning under its own name; `--camera FILE` takes a calibrated camera.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "app/cli/common_flags.hpp"
#include "app/camera_flags.hpp"
#include "catalog/database_recipe.hpp"
#include "app/command.hpp"
#include "common/output_file.hpp"
#include "catalog/star_catalog.hpp"
#include "catalog/star_database.hpp"
#include "common/conventions.hpp"
#include "common/errors.hpp"
#include "common/log.hpp"

namespace st::app {
namespace {

struct CatalogBuildOptions {
  bool force = false;  ///< replace an existing -o
  std::string catalog_path = StarDatabase::defaultCatalogPath();
  std::string catalog_format = "auto";
  solve::CameraOptions camera;             // --camera / --camera-section / --fov-deg (horizontal)
  std::vector<int> size;            // --size W H with --fov-deg
  std::optional<double> diagonal_fov_deg;
  double margin_deg = 0.2;
  double mag_limit = 6.5;
  double epoch = 2025.0;
  bool no_aberration = false;
  bool no_parallax = false;
  std::optional<double> double_star_arcsec;  // unset: kUnresolvedDoubleSepPx of the camera
  int per_region = 0;                    // 0 = no density reduction (said so in the help)
  std::optional<double> region_deg;      // unset: half the pair angle
  std::optional<double> neighbour_deg;   // unset: half the diagonal
  std::string out;
};

std::string num(double v) {
  char b[40];
  std::snprintf(b, sizeof b, "%g", v);
  return b;
}

// InputError naming the flag and the value unless lo <(=) v <= hi (NaN never passes).
void requireIn(const char* flag, double v, double lo, double hi, bool lo_open,
               const std::string& hint = "") {
  const bool ok = std::isfinite(v) && (lo_open ? v > lo : v >= lo) && v <= hi;
  if (!ok)
    throw InputError(std::string(flag) + " " + num(v) + ": must be " + (lo_open ? "> " : ">= ") +
                     num(lo) + " and <= " + num(hi) + (hint.empty() ? "" : " (" + hint + ")"));
}

// The image diagonal the pair index must span, from the one camera option given; `how`
// describes it for the log; `pixel_scale` [rad/px] is set when the option gives one (not
// --diagonal-fov-deg).
double diagonalFov(const CatalogBuildOptions& o, std::string& how, double& pixel_scale) {
  pixel_scale = 0;
  const int given = int(!o.camera.camera_file.empty()) + int(o.camera.fov_deg > 0) +
                    int(o.diagonal_fov_deg.has_value());
  if (given != 1)
    throw InputError("catalog build needs exactly one of --fov-deg H (horizontal FOV, with "
                     "--size W H), --camera FILE or --diagonal-fov-deg D");
  if (!o.size.empty() && !(o.camera.fov_deg > 0))
    throw InputError("--size is the image size for --fov-deg; a --camera file has its own");
  char b[300];
  if (o.diagonal_fov_deg) {
    requireIn("--diagonal-fov-deg", *o.diagonal_fov_deg, 0.1, 170.0, false);
    std::snprintf(b, sizeof b, "a diagonal FOV of %.3f deg (--diagonal-fov-deg)",
                  *o.diagonal_fov_deg);
    how = b;
    return deg2rad(*o.diagonal_fov_deg);
  }
  if (!o.camera.camera_file.empty()) {
    const CameraModel cam = o.camera.resolve(0, 0);
    std::snprintf(b, sizeof b, "the %dx%d camera of %s: diagonal FOV %.3f deg", cam.width(),
                  cam.height(), o.camera.camera_file.c_str(), rad2deg(2 * cam.halfDiagonalFov()));
    how = b;
    pixel_scale = cam.pixelScale();
    return 2 * cam.halfDiagonalFov();
  }
  requireIn("--fov-deg", o.camera.fov_deg, 0.1, 179.0, false);
  const bool square = o.size.empty();
  const int w = square ? 1024 : o.size[0], h = square ? 1024 : o.size[1];
  if (w < 1 || h < 1)
    throw InputError("--size " + std::to_string(w) + " " + std::to_string(h) +
                     ": width and height must be >= 1 px");
  const CameraModel cam = CameraModel::fromFov(w, h, deg2rad(o.camera.fov_deg));
  const double diag = 2 * cam.halfDiagonalFov();
  if (!(diag < deg2rad(170.0)))
    throw InputError("--fov-deg " + num(o.camera.fov_deg) + " with --size " + std::to_string(w) +
                     " " + std::to_string(h) + ": the diagonal would exceed 170 deg");
  if (square)
    log::warn(
        "--fov-deg %g is the HORIZONTAL field of view (as in solve and "
        "camera files); without --size W H the image is taken as square, so pairs "
        "span its diagonal, %.3f deg. Before issue 21 this option meant the diagonal: "
        "for that, use --diagonal-fov-deg.",
        o.camera.fov_deg, rad2deg(diag));
  std::snprintf(b, sizeof b, "a %s %dx%d image of %.3f deg horizontal FOV: diagonal %.3f deg",
                square ? "square" : "", w, h, o.camera.fov_deg, rad2deg(diag));
  how = b;
  pixel_scale = cam.pixelScale();
  return diag;
}

// Every number of the build, checked before any work or output (the camera's in diagonalFov).
void checkNumbers(const CatalogBuildOptions& o) {
  requireIn("--margin-deg", o.margin_deg, 0.0, 10.0, false);
  requireIn("--mag-limit", o.mag_limit, -30.0, 30.0, false);
  requireIn("--epoch", o.epoch, 1000.0, 3000.0, false, "a Julian year, e.g. 2026.9");
  if (o.double_star_arcsec)
    requireIn("--double-star-arcsec", *o.double_star_arcsec, 0.0, 3599.0, false, "0 = no merge");
  if (o.per_region < 0)
    throw InputError("--per-region " + std::to_string(o.per_region) +
                     ": must be >= 1, or 0 for no density reduction");
  if (o.region_deg) {
    if (o.per_region == 0)
      throw InputError("--region-deg is the cone of --per-region N; give --per-region too");
    requireIn("--region-deg", *o.region_deg, 0.0, 90.0, true,
              "omit it for half the pair angle");
  }
  if (o.neighbour_deg)
    requireIn("--neighbour-deg", *o.neighbour_deg, 0.0, 90.0, true,
              "the neighbour table cannot be empty; omit the option for half the diagonal");
}

DatabaseParams buildParams(const CatalogBuildOptions& o, double diag, double pixel_scale) {
  DatabaseParams p{};
  p.max_pair_angle = diag + deg2rad(o.margin_deg);
  if (!(p.max_pair_angle < kPi))
    throw InputError("--margin-deg " + num(o.margin_deg) + ": diagonal + margin reaches 180 deg");
  p.mag_limit = o.mag_limit;
  p.epoch_jyear = o.epoch;
  p.aberration = !o.no_aberration;
  p.parallax = !o.no_parallax;
  // One rule with solve and the trackers' databases: unresolved doubles, from the optics.
  if (o.double_star_arcsec)
    p.double_star_sep = arcsec2rad(*o.double_star_arcsec);
  else if (pixel_scale > 0)
    p.double_star_sep = kUnresolvedDoubleSepPx * pixel_scale;
  else
    throw InputError("--diagonal-fov-deg gives no pixel scale for the double-star merge: give "
                     "--double-star-arcsec (" + num(kUnresolvedDoubleSepPx) +
                     " px of the camera: stars closer are one image peak), or the camera with "
                     "--fov-deg/--size or --camera");
  p.max_stars_per_region = o.per_region;
  p.region_radius = o.region_deg ? deg2rad(*o.region_deg) : p.max_pair_angle / 2;
  p.neighbour_radius = o.neighbour_deg ? deg2rad(*o.neighbour_deg) : diag / 2;
  return p;
}

void printDatabase(const StarDatabase& db, const std::string& path) {
  const DatabaseParams& p = db.params();
  const BuildReport& r = db.report();
  std::printf("star database %s\n", path.c_str());
  if (std::filesystem::exists(path))
    std::printf("  file size            %.2f MB\n", std::filesystem::file_size(path) / 1e6);
  std::printf("  catalog              %s (epoch J%.2f)\n", r.catalog_name.c_str(),
              r.catalog_epoch_jyear);
  if (!r.catalog_path.empty())
    std::printf("  catalog file         %s (depth V %.2f)\n", r.catalog_path.c_str(),
                r.catalog_depth_vmag);
  std::printf("  epoch                J%.3f  proper motion on, parallax %s, aberration %s\n",
              p.epoch_jyear, p.parallax ? "on" : "off", p.aberration ? "on" : "off");
  std::printf("  max pair angle       %.3f deg\n", rad2deg(p.max_pair_angle));
  if (r.requested_mag_limit > p.mag_limit)
    std::printf("  magnitude limit      V <= %.2f (asked V <= %.2f, beyond the catalog's depth)\n",
                p.mag_limit, r.requested_mag_limit);
  else
    std::printf("  magnitude limit      V <= %.2f\n", p.mag_limit);
  std::printf("  double-star merge    %.2f arcsec\n", rad2arcsec(p.double_star_sep));
  if (p.max_stars_per_region > 0)
    std::printf("  uniform density      %d brightest per %.2f deg cone\n", p.max_stars_per_region,
                rad2deg(p.region_radius > 0 ? p.region_radius : p.max_pair_angle / 2));
  else
    std::printf("  uniform density      off\n");
  std::printf("  neighbour radius     %.3f deg\n", rad2deg(p.neighbour_radius));
  std::printf("counts\n");
  std::printf("  catalog entries      %zu (+%zu without position, skipped)\n", r.catalog_entries,
              r.skipped_no_position);
  std::printf("  merge candidates     %zu\n", r.merge_candidates);
  std::printf("  double-star groups   %zu (%zu stars absorbed)\n", r.double_star_groups,
              r.stars_merged_away);
  std::printf("  after mag limit      %zu\n", r.after_mag_limit);
  std::printf("  after density        %zu\n", r.after_density);
  std::printf("  stars                %zu\n", db.stars().size());
  std::printf("  blend-screen stars   %zu (not identified; their light screens tracking windows)\n",
              db.screenStars().size());
  std::printf("  pairs                %zu\n", db.pairs().size());
  std::printf("  k-vector size        %zu\n", db.pairKVector().size());
  std::printf("  neighbour entries    %zu (%.1f per star)\n", r.neighbour_entries,
              db.stars().empty() ? 0.0 : double(r.neighbour_entries) / db.stars().size());
}

int runBuild(const CatalogBuildOptions& o) {
  checkNumbers(o);
  std::string how;
  double pixel_scale = 0;
  const double diag = diagonalFov(o, how, pixel_scale);
  const DatabaseParams p = buildParams(o, diag, pixel_scale);
  refuseSameFile(o.out, "--output",
                 {{o.catalog_path, "--catalog"}, {o.camera.camera_file, "--camera"}});
  prepareOutputFile(o.out, "--output", o.force);
  log::info("camera: %s; pairs up to %.3f deg", how.c_str(), rad2deg(p.max_pair_angle));
  log::info("loading %s", o.catalog_path.c_str());
  const StarCatalog cat = loadCatalog(o.catalog_path, o.catalog_format);
  log::info(
      "%s: %zu entries (%zu without position skipped, %zu without V), "
      "depth V %.2f (faintest %.2f)",
      cat.format.c_str(), cat.entries.size(), cat.skipped_no_position, cat.skipped_no_magnitude,
      cat.depth_vmag, cat.faintest_vmag);
  double brightest = cat.entries.front().vmag;
  for (const CatalogEntry& e : cat.entries) brightest = std::min(brightest, e.vmag);
  if (o.mag_limit < brightest)
    throw InputError("--mag-limit " + num(o.mag_limit) + ": no star of " + o.catalog_path +
                     " is that bright (its brightest is V " + num(brightest) +
                     "); the database would be empty");
  const StarDatabase db =
      StarDatabase::build(cat, p, [](const std::string& m) { log::info("%s", m.c_str()); });
  log::info("built in %.3f s; writing %s", db.report().build_seconds, o.out.c_str());
  db.save(o.out);
  printDatabase(db, o.out);
  return kExitOk;
}

}  // namespace

void addCatalogCommand(CLI::App& root, CommandRun& run) {
  auto* cmd = root.add_subcommand("catalog", "Build or inspect the star database (ground program)");
  cmd->require_subcommand(1);

  auto o = std::make_shared<CatalogBuildOptions>();
  auto* build = cmd->add_subcommand("build", "Build a star database file from a star catalog");
  std::vector<std::string> formats = {"auto"};
  for (const std::string& f : catalogFormats()) formats.push_back(f);
  build->add_option("--catalog", o->catalog_path,
                    "Star catalog: Hipparcos hip_main.dat, Tycho-2 tyc2.dat (plain or .gz) or "
                    "BSC5 binary (default: the committed Hipparcos subset, V <= 6.6)");
  build->add_option("--catalog-format", o->catalog_format,
                    "Format of --catalog (auto: from the file name, else its content)")
      ->check(CLI::IsMember(formats))
      ->capture_default_str();
  addCameraFlags(*build, o->camera);
  build->add_option("--size", o->size, "Image size W H [px] for --fov-deg (default: square)")
      ->expected(2);
  build->add_option("--diagonal-fov-deg", o->diagonal_fov_deg,
                    "The image diagonal [deg], instead of --fov-deg/--camera");
  build->add_option("--margin-deg", o->margin_deg, "Added to the diagonal for the pair index [deg]")
      ->capture_default_str();
  build->add_option("--mag-limit", o->mag_limit,
                    "Keep stars with V <= this (capped, with a warning, at the catalog's depth)")
      ->capture_default_str();
  build->add_option("--epoch", o->epoch,
                    "Observation epoch, Julian year (e.g. 2019.57); the default is a fixed "
                    "2025.0 so that one command always builds the same file (solve and "
                    "calibrate take a frame's own date; solve says when a database's epoch "
                    "is too far from it)")
      ->capture_default_str();
  build->add_flag("--no-aberration", o->no_aberration, "Do not apply annual aberration");
  build->add_flag("--no-parallax", o->no_parallax, "Do not apply annual parallax");
  build->add_option("--double-star-arcsec", o->double_star_arcsec,
                    "Merge stars closer than this (0 = off) [arcsec] (default: 1.5 px of the "
                    "camera, the rule solve and the trackers use: closer stars are one image "
                    "peak; needed with --diagonal-fov-deg)");
  build->add_option("--per-region", o->per_region,
                    "Uniform density: keep the N brightest per cone (0 = off)")
      ->capture_default_str();
  build->add_option("--region-deg", o->region_deg,
                    "Radius of the density cones [deg] (default: half the pair angle)");
  build->add_option("--neighbour-deg", o->neighbour_deg,
                    "Radius of the star-neighbourhood table [deg] (default: half the diagonal)");
  build->add_option("-o,--output", o->out, "Database file to write")->required();
  cli::addForceFlag(*build, o->force);
  build->callback([o, &run] {
    run = [o] { return runBuild(*o); };
  });

  auto info_path = std::make_shared<std::string>();
  auto* info = cmd->add_subcommand("info", "Print the parameters and counts of a database file");
  info->add_option("file", *info_path, "Star database file")->required();
  info->callback([info_path, &run] {
    run = [info_path] {
      printDatabase(StarDatabase::load(*info_path), *info_path);
      return kExitOk;
    };
  });
}

}  // namespace st::app

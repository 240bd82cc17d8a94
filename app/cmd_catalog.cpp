// `startracker catalog build|info`: the ground program. Builds the star database (pairs +
// k-vector, cone index, neighbour table) from a real catalog for a camera FOV and magnitude
// limit, and prints what a database file holds.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include "app/command.hpp"
#include "catalog/star_catalog.hpp"
#include "catalog/star_database.hpp"
#include "common/conventions.hpp"
#include "common/errors.hpp"

namespace st::app {
namespace {

struct CatalogBuildOptions {
  std::string catalog_path = StarDatabase::defaultCatalogPath();
  double fov_deg = 0;
  double margin_deg = 0.2;
  double mag_limit = 6.5;
  double epoch = 2025.0;
  bool no_aberration = false;
  bool no_parallax = false;
  double double_star_arcsec = 10.0;
  int per_region = 0;
  double region_deg = 0;
  double neighbour_deg = 0;
  std::string out;
};

void printDatabase(const StarDatabase& db, const std::string& path) {
  const DatabaseParams& p = db.params();
  const BuildReport& r = db.report();
  std::printf("star database %s\n", path.c_str());
  if (std::filesystem::exists(path))
    std::printf("  file size            %.2f MB\n", std::filesystem::file_size(path) / 1e6);
  std::printf("  catalog              %s (epoch J%.2f)\n", r.catalog_name.c_str(),
              r.catalog_epoch_jyear);
  std::printf("  epoch                J%.3f  proper motion on, parallax %s, aberration %s\n",
              p.epoch_jyear, p.parallax ? "on" : "off", p.aberration ? "on" : "off");
  std::printf("  max pair angle       %.3f deg\n", rad2deg(p.max_pair_angle));
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
  std::printf("  pairs                %zu\n", db.pairs().size());
  std::printf("  k-vector size        %zu\n", db.pairKVector().size());
  std::printf("  neighbour entries    %zu (%.1f per star)\n", r.neighbour_entries,
              db.stars().empty() ? 0.0 : double(r.neighbour_entries) / db.stars().size());
}

}  // namespace

void addCatalogCommand(CLI::App& root, CommandRun& run) {
  auto* cmd = root.add_subcommand("catalog", "Build or inspect the star database (ground program)");
  cmd->require_subcommand(1);

  auto o = std::make_shared<CatalogBuildOptions>();
  auto* build = cmd->add_subcommand("build", "Build a star database file from a star catalog");
  build->add_option("--catalog", o->catalog_path,
                    "Hipparcos hip_main.dat (.gz) or BSC5 binary (default: the committed subset)");
  build->add_option("--fov-deg", o->fov_deg,
                    "Largest star separation in one image: the camera's diagonal FOV [deg]")
      ->required()
      ->check(CLI::Range(0.1, 120.0));
  build->add_option("--margin-deg", o->margin_deg, "Added to --fov-deg for the pair index [deg]")
      ->capture_default_str();
  build->add_option("--mag-limit", o->mag_limit, "Keep stars with V <= this")->capture_default_str();
  build->add_option("--epoch", o->epoch, "Observation epoch, Julian year (e.g. 2019.57)")
      ->capture_default_str();
  build->add_flag("--no-aberration", o->no_aberration, "Do not apply annual aberration");
  build->add_flag("--no-parallax", o->no_parallax, "Do not apply annual parallax");
  build->add_option("--double-star-arcsec", o->double_star_arcsec,
                    "Merge stars closer than this (0 = off) [arcsec]")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 3600.0));
  build->add_option("--per-region", o->per_region,
                    "Uniform density: keep the N brightest per cone (0 = off)")
      ->check(CLI::NonNegativeNumber);
  build->add_option("--region-deg", o->region_deg,
                    "Radius of the density cones [deg] (default: half of --fov-deg)");
  build->add_option("--neighbour-deg", o->neighbour_deg,
                    "Radius of the star-neighbourhood table [deg] (default: half of --fov-deg)");
  build->add_option("-o,--output", o->out, "Database file to write")->required();
  build->callback([o, &run] {
    run = [o] {
      const double fov = deg2rad(o->fov_deg);
      DatabaseParams p{};
      p.max_pair_angle = fov + deg2rad(o->margin_deg);
      p.mag_limit = o->mag_limit;
      p.epoch_jyear = o->epoch;
      p.aberration = !o->no_aberration;
      p.parallax = !o->no_parallax;
      p.double_star_sep = arcsec2rad(o->double_star_arcsec);
      p.max_stars_per_region = o->per_region;
      p.region_radius = deg2rad(o->region_deg);
      p.neighbour_radius = o->neighbour_deg > 0 ? deg2rad(o->neighbour_deg) : fov / 2;
      std::fprintf(stderr, "[catalog] loading %s\n", o->catalog_path.c_str());
      const StarCatalog cat = loadCatalog(o->catalog_path);
      std::fprintf(stderr, "[catalog] %zu entries (%zu without position skipped, %zu without V)\n",
                   cat.entries.size(), cat.skipped_no_position, cat.skipped_no_magnitude);
      const StarDatabase db = StarDatabase::build(cat, p, [](const std::string& m) {
        std::fprintf(stderr, "[catalog] %s\n", m.c_str());
      });
      std::fprintf(stderr, "[catalog] built in %.3f s; writing %s\n", db.report().build_seconds,
                   o->out.c_str());
      db.save(o->out);
      printDatabase(db, o->out);
      return kExitOk;
    };
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

// `startracker testbed draw|photograph|solve`: the near-field star display of seed 001
// (sensors/testbed/) for a real bench: draw the sky onto an image the size of the screen,
// simulate a camera photograph of it, and solve camera images of the screen with the
// iterative near-field method (per-update stars matched and attitude, --json).
#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "app/cli/common_flags.hpp"
#include "app/camera_flags.hpp"
#include "app/cli/validators.hpp"
#include "app/command.hpp"
#include "imageio/image_file.hpp"
#include "common/output_file.hpp"
#include "app/testbed/star_list.hpp"
#include "catalog/star_catalog.hpp"
#include "catalog/star_database.hpp"
#include "common/conventions.hpp"
#include "common/errors.hpp"
#include "sensors/detect/star_detector.hpp"
#include "sensors/testbed/display_image.hpp"
#include "sensors/testbed/near_field_solver.hpp"

namespace st::app {
namespace {

using testbed::DisplayGeometry;

/// The bench's geometry flags, defaults from DisplayGeometry (display_geometry.hpp).
struct GeometryArgs {
  DisplayGeometry d;
  std::vector<int> screen_px = {d.screen_width_px, d.screen_height_px};
  std::vector<double> screen_mm = {d.screen_width_m * 1e3, d.screen_height_m * 1e3};
  std::vector<double> lever = {d.lever_arm_m.x(), d.lever_arm_m.y(), d.lever_arm_m.z()};
  std::vector<double> centre = {d.screen_centre_m.x(), d.screen_centre_m.y()};
  double distance_m = d.screen_distance_m;

  void addTo(CLI::App* c) {
    using cli::Bound;
    using cli::Number;
    // 16384 px a side: twice an 8K display; 100000 px asked OpenCV for 40 GB (issue 39).
    c->add_option("--screen-px", screen_px, "Screen size W H [px]")->expected(2)
        ->check(cli::WholeNumber(16, 16384))->capture_default_str();
    c->add_option("--screen-mm", screen_mm, "Screen's visible area W H [mm]")->expected(2)
        ->check(Number(0, 1e5, Bound::kOpen))->capture_default_str();
    c->add_option("--distance-m", distance_m,
                  "h: centre of rotation to the screen plane [m] (seed 001: 1.7695)")
        ->check(Number(0, 1e4, Bound::kOpen))->capture_default_str();
    c->add_option("--lever-arm-m", lever,
                  "R_0: camera optical centre from the centre of rotation, body axes x y z [m]")
        ->expected(3)->check(Number(-1e3, 1e3))->capture_default_str();
    c->add_option("--screen-centre-m", centre,
                  "Screen centre's x y in the testbed frame [m] (default: above the camera)")
        ->expected(2)->check(Number(-1e3, 1e3))->capture_default_str();
  }
  DisplayGeometry resolve() const {
    DisplayGeometry g;
    g.screen_width_px = screen_px[0];
    g.screen_height_px = screen_px[1];
    g.screen_width_m = screen_mm[0] * 1e-3;
    g.screen_height_m = screen_mm[1] * 1e-3;
    g.screen_distance_m = distance_m;
    g.lever_arm_m = Vec3(lever[0], lever[1], lever[2]);
    g.screen_centre_m = Vec2(centre[0], centre[1]);
    if (std::string why; !g.isValid(&why))
      throw InputError("--distance-m/--lever-arm-m/--screen-*: " + why);
    return g;
  }
};

Quat yprDeg(const std::vector<double>& v) {
  return testbed::quatFromYpr(Vec3(deg2rad(v[0]), deg2rad(v[1]), deg2rad(v[2])));
}
Vec3 toYprDeg(const Quat& q) { return testbed::yprFromQuat(q) * kDegPerRad; }

std::string withExtension(const std::string& path, const std::string& ext) {
  const auto dot = path.find_last_of('.');
  const auto slash = path.find_last_of('/');
  const bool has = dot != std::string::npos && (slash == std::string::npos || dot > slash);
  return (has ? path.substr(0, dot) : path) + ext;
}

// ---- draw ----
struct DrawArgs {
  GeometryArgs geo;
  std::vector<double> ypr = {0, 0, 0};
  double mag_limit = 4.5;
  int max_stars = 12;
  double dot_sigma_px = 3.0;
  std::string catalog, output;
  bool force = false;
};

int runDraw(const DrawArgs& a) {
  const DisplayGeometry g = a.geo.resolve();
  prepareOutputFile(a.output, "-o/--output", a.force);
  prepareOutputFile(withExtension(a.output, ".csv"), "-o/--output's star list", a.force);
  const StarCatalog cat =
      loadCatalog(a.catalog.empty() ? StarDatabase::defaultCatalogPath() : a.catalog);
  std::vector<Vec3> u;
  std::vector<double> mag;
  std::vector<uint32_t> id;
  for (const CatalogEntry& e : cat.entries)
    if (e.vmag <= a.mag_limit) {
      u.push_back(unitVectorFromRaDec(e.ra, e.dec));  // catalog epoch: a display needs no more
      mag.push_back(e.vmag);
      id.push_back(e.id);
    }
  DisplayStarList list;
  list.attitude_ypr_deg = Vec3(a.ypr[0], a.ypr[1], a.ypr[2]);
  list.stars = testbed::skyOnDisplay(g, u, mag, id, yprDeg(a.ypr), a.max_stars);
  testbed::DrawOptions o;
  o.dot_sigma_px = a.dot_sigma_px;
  imageio::writeImage(a.output, testbed::drawDisplay(g, list.stars, o));
  const std::string csv = withExtension(a.output, ".csv");
  writeStarList(csv, list);
  std::printf("testbed draw: %zu stars V <= %g on a %dx%d px screen -> %s, star list %s\n",
              list.stars.size(), a.mag_limit, g.screen_width_px, g.screen_height_px,
              a.output.c_str(), csv.c_str());
  if (list.stars.size() < 3)
    std::printf("warning: fewer than 3 stars on the screen: raise --mag-limit or turn the "
                "attitude\n");
  return kExitOk;
}

// ---- photograph ----
struct PhotoArgs {
  GeometryArgs geo;
  solve::CameraOptions camera;
  std::vector<int> size = {640, 480};
  std::vector<double> ypr = {0, 0, 0};
  double noise_adu = 2.0;
  uint64_t seed = 1;
  std::string screen, output;
  bool force = false;
};

int runPhotograph(const PhotoArgs& a) {
  const DisplayGeometry g = a.geo.resolve();
  prepareOutputFile(a.output, "-o/--output", a.force);
  const CameraModel cam = a.camera.resolve(a.size[0], a.size[1]);
  const cv::Mat screen = imageio::loadImage(a.screen).image;
  if (screen.cols != g.screen_width_px || screen.rows != g.screen_height_px)
    throw InputError(a.screen + ": " + std::to_string(screen.cols) + "x" +
                     std::to_string(screen.rows) + " px, but --screen-px is " +
                     std::to_string(g.screen_width_px) + " " + std::to_string(g.screen_height_px));
  cv::Mat eight;
  screen.convertTo(eight, CV_8U, screen.depth() == CV_16U ? 1.0 / 257 : 1.0);
  imageio::writeImage(a.output,
             testbed::photographDisplay(eight, g, cam, yprDeg(a.ypr), a.noise_adu, a.seed));
  std::printf("testbed photograph: %s seen by a %dx%d camera at platform yaw/pitch/roll %g %g "
              "%g deg -> %s\n",
              a.screen.c_str(), cam.width(), cam.height(), a.ypr[0], a.ypr[1], a.ypr[2],
              a.output.c_str());
  return kExitOk;
}

// ---- solve ----
struct SolveArgs {
  GeometryArgs geo;
  solve::CameraOptions camera;
  std::vector<std::string> images;
  std::string stars;
  std::vector<double> prediction = {0, 0, 0};
  int iterations = 3;
  double tolerance_arcsec = 250;
  std::string solver = WahbaSolver::defaultName();
  bool json = false;
};

int runSolve(const SolveArgs& a) {
  const DisplayGeometry g = a.geo.resolve();
  const DisplayStarList list = readStarList(a.stars);
  std::vector<Vec2> px;
  for (const auto& s : list.stars) {
    if (!g.isOnScreen(s.screen_px))
      throw InputError(a.stars + ": star " + std::to_string(s.id) +
                       " is off the screen given by --screen-px");
    px.push_back(s.screen_px);
  }
  testbed::NearFieldOptions no;
  no.iterations = a.iterations;
  no.tolerance = arcsec2rad(a.tolerance_arcsec);
  no.solver = a.solver;
  const testbed::NearFieldSolver solver(g, testbed::displayDatabase(g, px), no);
  const Quat q_sky_I = yprDeg({list.attitude_ypr_deg.x(), list.attitude_ypr_deg.y(),
                               list.attitude_ypr_deg.z()});
  nlohmann::ordered_json all = nlohmann::ordered_json::array();
  bool all_ok = true;
  for (const std::string& path : a.images) {
    const cv::Mat img = imageio::loadImage(path).image;
    const CameraModel cam = a.camera.resolve(img.cols, img.rows);
    const DetectionResult det = detectStars(img);
    std::vector<Vec3> b;
    for (const Centroid& c : det.stars) b.push_back(cam.pixelToVector(c.px));  // brightest first
    const testbed::NearFieldResult r = solver.solve(b, yprDeg(a.prediction));
    all_ok &= r.ok();
    nlohmann::ordered_json j;
    j["image"] = path;
    j["detected"] = b.size();
    j["ok"] = r.ok();
    j["updates"] = nlohmann::ordered_json::array();
    if (!a.json) std::printf("%s: %zu stars detected\n", path.c_str(), b.size());
    for (std::size_t k = 0; k < r.passes.size(); ++k) {
      const auto& p = r.passes[k];
      const Vec3 ypr = toYprDeg(p.q_ib);
      nlohmann::ordered_json u;
      u["update"] = k + 1;
      u["ok"] = p.ok;
      u["stars_matched"] = p.stars_matched;
      u["angles_unique"] = p.angles_unique;
      u["angles_ambiguous"] = p.angles_ambiguous;
      u["platform_ypr_deg"] = {ypr.x(), ypr.y(), ypr.z()};
      if (!p.ok) u["reason"] = p.reason;
      j["updates"].push_back(u);
      if (!a.json)
        std::printf("  update %zu: %d stars matched (%d angles unique, %d ambiguous), platform "
                    "yaw/pitch/roll %.4f %.4f %.4f deg%s%s\n",
                    k + 1, p.stars_matched, p.angles_unique, p.angles_ambiguous, ypr.x(), ypr.y(),
                    ypr.z(), p.ok ? "" : " -- ", p.ok ? "" : p.reason.c_str());
    }
    if (r.ok()) {
      // The body's attitude in the sky. Its +z is not where the screen's stars are: the
      // database directions are from the centre of rotation, and the screen hangs above the
      // camera, off that centre's vertical.
      const Quat q_sky_body = q_sky_I * r.q_ib();
      const RaDecRoll rdr = raDecRollFromAttitude(q_sky_body);
      const Vec3 ypr = toYprDeg(r.q_ib());
      j["platform_ypr_deg"] = {ypr.x(), ypr.y(), ypr.z()};
      j["sky_ra_dec_roll_deg"] = {rad2deg(rdr.ra), rad2deg(rdr.dec), rad2deg(rdr.roll)};
      if (!a.json)
        std::printf("  platform yaw/pitch/roll %.4f %.4f %.4f deg; in the sky (body +z): RA %.4f "
                    "Dec %.4f roll %.4f deg\n",
                    ypr.x(), ypr.y(), ypr.z(), rad2deg(rdr.ra), rad2deg(rdr.dec),
                    rad2deg(rdr.roll));
    } else if (!a.json) {
      std::printf("  no attitude: %s\n", r.passes.back().reason.c_str());
    }
    all.push_back(j);
  }
  if (a.json) std::printf("%s\n", all.dump(2).c_str());
  return all_ok ? kExitOk : kExitFailure;
}

}  // namespace

void addTestbedCommand(CLI::App& root, CommandRun& run) {
  auto* cmd = root.add_subcommand(
      "testbed", "Near-field star display testbed (seed 001): draw the sky for a screen, "
                 "simulate the camera's photograph, solve camera images of the screen");
  cmd->require_subcommand(1);
  using cli::Number;
  auto ypr_check = Number(-360, 360);

  auto* draw = cmd->add_subcommand("draw", "Draw the stars a screen must show so that the "
                                           "testbed frame has the given sky attitude");
  auto d = std::make_shared<DrawArgs>();
  d->geo.addTo(draw);
  draw->add_option("--attitude-ypr-deg", d->ypr,
                   "Yaw pitch roll [deg] of the testbed frame in the sky (ICRS; 0 0 0 = the "
                   "screen shows the north celestial pole)")
      ->expected(3)->check(ypr_check)->capture_default_str();
  draw->add_option("--mag-limit", d->mag_limit, "Faintest V magnitude drawn")
      ->check(Number(-2, 20))->capture_default_str();
  draw->add_option("--max-stars", d->max_stars, "At most this many (the brightest) stars: the "
                   "angle match needs few")
      ->check(cli::WholeNumber(3, 1000))->capture_default_str();
  draw->add_option("--dot-sigma-px", d->dot_sigma_px, "Gaussian dot 1-sigma [screen px]")
      ->check(Number(0.3, 100))->capture_default_str();
  draw->add_option("--catalog", d->catalog, "Star catalog (default: the committed Hipparcos subset)");
  draw->add_option("-o,--output", d->output, "Screen image (.png); the star list goes beside it "
                   "as .csv")->required();
  cli::addForceFlag(*draw, d->force);
  draw->callback([d, &run] { run = [d] { return runDraw(*d); }; });

  auto* photo = cmd->add_subcommand("photograph", "Simulate the camera's image of a screen image "
                                                  "at a platform attitude");
  auto p = std::make_shared<PhotoArgs>();
  p->geo.addTo(photo);
  addCameraFlags(*photo, p->camera);
  photo->add_option("screen", p->screen, "Screen image (from testbed draw)")->required();
  photo->add_option("--size", p->size, "Camera image W H with --fov-deg")->expected(2)
      ->check(cli::WholeNumber(16, 16384))->capture_default_str();
  photo->add_option("--attitude-ypr-deg", p->ypr, "Platform yaw pitch roll [deg]")->expected(3)
      ->check(ypr_check)->capture_default_str();
  photo->add_option("--noise-adu", p->noise_adu, "Read noise 1-sigma [ADU]")
      ->check(Number(0, 100))->capture_default_str();
  photo->add_option("--seed", p->seed, "Noise seed")
      ->check(cli::WholeNumber(0, cli::kMaxU64))->capture_default_str();
  photo->add_option("-o,--output", p->output, "Camera image (.png)")->required();
  cli::addForceFlag(*photo, p->force);
  photo->callback([p, &run] { run = [p] { return runPhotograph(*p); }; });

  auto* solve = cmd->add_subcommand("solve", "Solve camera images of the screen by the "
                                             "iterative near-field method (seed 001 sec. IV.B)");
  auto s = std::make_shared<SolveArgs>();
  s->geo.addTo(solve);
  addCameraFlags(*solve, s->camera);
  solve->add_option("images", s->images, "Camera images of the screen")->required();
  solve->add_option("--stars", s->stars, "Star list written by testbed draw (the display "
                    "database)")->required();
  solve->add_option("--prediction-ypr-deg", s->prediction,
                    "Predicted platform yaw pitch roll [deg] (the first update's prediction)")
      ->expected(3)->check(ypr_check)->capture_default_str();
  solve->add_option("--iterations", s->iterations, "Updates: each estimate is the next "
                    "prediction")->check(cli::WholeNumber(1, 100))->capture_default_str();
  solve->add_option("--tolerance-arcsec", s->tolerance_arcsec,
                    "Half-width of the angle match (seed 001: 500\" accuracy = 250)")
      ->check(Number(0, 36000, cli::Bound::kOpen))->capture_default_str();
  solve->add_option("--solver", s->solver, "Wahba solver")
      ->check(CLI::IsMember(WahbaSolver::names()))->capture_default_str();
  solve->add_flag("--json", s->json, "Print JSON");
  solve->callback([s, &run] { run = [s] { return runSolve(*s); }; });
}

}  // namespace st::app

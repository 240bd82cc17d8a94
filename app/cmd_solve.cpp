// `startracker solve IMAGE`: lost-in-space on one image. Detect stars, identify them
// (sensors/identify, any registered algorithm), solve the attitude (any Wahba solver) and
// print the attitude, RA/Dec/roll of the boresight, its 1-sigma errors, the matched stars
// and the time per stage; `--json` prints one JSON object for scripts.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <memory>
#include <sstream>

#include "app/annotate.hpp"
#include "app/camera_options.hpp"
#include "app/command.hpp"
#include "catalog/database_recipe.hpp"
#include "app/image_io.hpp"
#include "catalog/star_catalog.hpp"
#include "catalog/star_database.hpp"
#include "common/conventions.hpp"
#include "common/errors.hpp"
#include "sensors/attitude/wahba.hpp"
#include "sensors/detect/star_detector.hpp"
#include "sensors/identify/fov_search.hpp"
#include "sensors/identify/identifier.hpp"

namespace st::app {
namespace {

struct SolveOptions {
  std::string image;
  CameraOptions camera;
  std::string database;
  std::string algorithm = StarIdentifier::defaultName();
  std::string solver = "quest";
  bool json = false;
  std::vector<double> fov_range_deg = {5.0, 30.0};
  double mag_limit = 6.6;
  double epoch = 0;  // 0 = from the image, else today
  int max_stars = 12;
  double min_sigma_px = -1;  // <0: 0.5 px without a camera file, 0.1 px with one
  std::string annotate;      // PNG path for a labelled picture of the solved frame
};

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

double todayJulianYear() { return julianYearFromUnixSeconds(static_cast<double>(std::time(nullptr))); }

std::string jsonNum(double v) {
  if (!std::isfinite(v)) return "null";
  char b[40];
  std::snprintf(b, sizeof b, "%.10g", v);
  return b;
}

int run(const SolveOptions& o) {
  const auto t_start = Clock::now();
  // --- image ---
  auto t0 = Clock::now();
  const LoadedImage img = loadImage(o.image);
  const double load_ms = msSince(t0);
  const int w = img.image.cols, h = img.image.rows;
  double epoch = o.epoch;
  std::string epoch_source = "--epoch";
  if (epoch <= 0) {
    epoch = img.epoch_jyear ? *img.epoch_jyear : todayJulianYear();
    epoch_source = img.epoch_jyear ? img.epoch_source : "today";
  }

  // --- detection ---
  t0 = Clock::now();
  const DetectionResult det = detectStars(img.image);
  const double detect_ms = msSince(t0);

  // --- cameras to try ---
  std::vector<double> grid;
  const double scale_tol = 0.02;
  std::unique_ptr<CameraModel> fixed_cam;
  if (o.camera.given()) {
    fixed_cam = std::make_unique<CameraModel>(o.camera.resolve(w, h));
  } else {
    if (o.fov_range_deg.size() != 2 || o.fov_range_deg[0] <= 0 ||
        o.fov_range_deg[1] < o.fov_range_deg[0])
      throw InputError("--fov-range needs MIN MAX in degrees with 0 < MIN <= MAX");
    grid = fovSearchGrid(deg2rad(o.fov_range_deg[0]), deg2rad(o.fov_range_deg[1]), scale_tol);
  }
  const double max_diag =
      fixed_cam ? 2 * fixed_cam->halfDiagonalFov()
                : 2 * CameraModel::fromFov(w, h, grid.back()).halfDiagonalFov() * (1 + scale_tol);

  // --- database ---
  t0 = Clock::now();
  StarDatabase db;
  std::string db_source;
  if (!o.database.empty()) {
    db = StarDatabase::load(o.database);
    db_source = o.database;
    if (db.params().max_pair_angle < max_diag * 0.999 && fixed_cam)
      std::fprintf(stderr, "[solve] warning: %s holds pairs up to %.2f deg, the image diagonal is "
                           "%.2f deg; stars far apart will not be paired\n",
                   o.database.c_str(), rad2deg(db.params().max_pair_angle), rad2deg(max_diag));
  } else {
    const StarCatalog cat = loadCatalog(StarDatabase::defaultCatalogPath());
    CameraDatabaseRecipe r;
    r.diagonal_fov_rad = max_diag;
    // The finest pixel scale in the search: doubles unresolved at every FOV tried.
    r.pixel_scale_rad = fixed_cam ? fixed_cam->pixelScale()
                                  : CameraModel::fromFov(w, h, grid.front()).pixelScale();
    r.mag_limit = o.mag_limit;
    r.epoch_jyear = epoch;
    r.aberration = true;
    db = StarDatabase::build(cat, databaseParams(r));
    char b[200];
    std::snprintf(b, sizeof b, "built in memory from %s (V <= %.1f, epoch %.2f from %s)",
                  StarDatabase::defaultCatalogPath().c_str(), o.mag_limit, epoch,
                  epoch_source.c_str());
    db_source = b;
  }
  const double db_ms = msSince(t0);

  // --- identification + attitude ---
  IdentifyOptions io;
  io.solver = o.solver;
  io.max_stars = o.max_stars;
  std::string err;
  auto identifier = StarIdentifier::create(o.algorithm, io, &err);
  if (!identifier) throw InputError("--algorithm: " + err);
  if (!WahbaSolver::create(o.solver, &err)) throw InputError("--solver: " + err);

  FovSearchResult fs;
  const double sigma_floor =
      o.min_sigma_px >= 0 ? o.min_sigma_px : (o.camera.camera_file.empty() ? 0.5 : 0.1);
  t0 = Clock::now();
  std::string failure;
  if (!det.reason.empty() || det.stars.size() < 3) {
    failure = "too few stars detected (" + std::to_string(det.stars.size()) + ")" +
              (det.reason.empty() ? "" : ": " + det.reason);
  } else if (fixed_cam) {
    // A FOV given without a camera file is approximate: allow 1 % and fit the focal length.
    const bool approx = o.camera.camera_file.empty();
    fs = identifyAndFit(det.stars, *fixed_cam, db, *identifier, approx ? 0.01 : 0.0, approx,
                        sigma_floor);
  } else {
    fs = identifyUnknownFov(det.stars, w, h, db, *identifier, grid, scale_tol, sigma_floor);
  }
  const double identify_ms = msSince(t0);
  const double total_ms = msSince(t_start);
  const IdentifyResult& r = fs.result;
  if (failure.empty() && !r.solved()) failure = r.reason;

  if (!failure.empty()) {
    if (o.json) {
      std::printf("{\"solved\": false, \"status\": \"%s\", \"reason\": \"%s\", \"stars_detected\": %zu}\n",
                  r.solved() ? "error" : toString(r.status), failure.c_str(), det.stars.size());
    }
    std::fprintf(stderr, "[solve] %s: not solved: %s\n", o.image.c_str(), failure.c_str());
    return kExitFailure;
  }

  const RaDecRoll rdr = raDecRollFromAttitude(r.q_ic);
  const AttitudeSigma sig = attitudeSigma(r.cov_cam);
  // No mounting here: the body frame is the camera frame, so q_ib below is q_ic.
  const Quat q = canonical(r.q_ic);
  const CameraModel& cam = fs.camera;
  const auto& stars = db.stars();

  if (!o.annotate.empty()) {
    std::vector<Vec2> detections;
    for (const Centroid& c : det.stars) detections.push_back(c.px);
    std::vector<LabelledStar> identified;
    for (const StarMatch& m : r.matches)
      identified.push_back({fs.obs[m.obs_index].px, "HIP " + std::to_string(m.catalog_id)});
    char l1[160], l2[160];
    std::snprintf(l1, sizeof l1, "RA %.4f  Dec %+.4f  roll %.3f deg", rad2deg(rdr.ra),
                  rad2deg(rdr.dec), rad2deg(rdr.roll));
    std::snprintf(l2, sizeof l2, "1-sigma %.1f\" cross-boresight, %.1f\" roll; %zu/%zu stars, RMS %.2f px",
                  rad2arcsec(sig.cross_boresight), rad2arcsec(sig.roll), r.matches.size(),
                  det.stars.size(), r.rms_residual_px);
    writeAnnotatedFrame(o.annotate, img.image, detections, identified, {l1, l2});
  }

  if (o.json) {
    std::ostringstream js;
    js << "{\"solved\": true, \"image\": \"" << o.image << "\", ";
    js << "\"ra_deg\": " << jsonNum(rad2deg(rdr.ra)) << ", \"dec_deg\": " << jsonNum(rad2deg(rdr.dec))
       << ", \"roll_deg\": " << jsonNum(rad2deg(rdr.roll)) << ", ";
    js << "\"q_ib\": [" << jsonNum(q.w()) << ", " << jsonNum(q.x()) << ", " << jsonNum(q.y())
       << ", " << jsonNum(q.z()) << "], ";
    js << "\"covariance\": [";
    for (int i = 0; i < 3; ++i) {
      js << (i ? ", [" : "[");
      for (int j = 0; j < 3; ++j) js << (j ? ", " : "") << jsonNum(r.cov_cam(i, j));
      js << "]";
    }
    js << "], ";
    js << "\"sigma_cross_boresight_arcsec\": " << jsonNum(rad2arcsec(sig.cross_boresight))
       << ", \"sigma_roll_arcsec\": " << jsonNum(rad2arcsec(sig.roll)) << ", ";
    js << "\"hfov_deg\": " << jsonNum(rad2deg(cam.horizontalFov())) << ", ";
    js << "\"algorithm\": \"" << r.algorithm << "\", \"solver\": \"" << o.solver << "\", ";
    js << "\"stars_detected\": " << det.stars.size() << ", \"stars_matched\": " << r.matches.size()
       << ", ";
    js << "\"rms_residual_arcsec\": " << jsonNum(rad2arcsec(r.rms_residual))
       << ", \"rms_residual_px\": " << jsonNum(r.rms_residual_px) << ", ";
    js << "\"false_match_probability\": " << jsonNum(r.false_match_probability) << ", ";
    js << "\"hypotheses_tried\": " << r.hypotheses_tried << ", \"fovs_tried\": " << fs.fovs_tried
       << ", ";
    js << "\"epoch_jyear\": " << jsonNum(epoch) << ", ";
    js << "\"stars\": [";
    for (std::size_t k = 0; k < r.matches.size(); ++k) {
      const StarMatch& m = r.matches[k];
      const Vec2& px = fs.obs[m.obs_index].px;
      js << (k ? ", " : "") << "{\"id\": " << m.catalog_id << ", \"x\": " << jsonNum(px.x())
         << ", \"y\": " << jsonNum(px.y()) << ", \"mag\": " << jsonNum(stars[m.star_index].mag)
         << ", \"residual_arcsec\": " << jsonNum(rad2arcsec(m.residual))
         << ", \"residual_px\": " << jsonNum(m.residual_px) << "}";
    }
    js << "], ";
    js << "\"timing_ms\": {\"load\": " << jsonNum(load_ms) << ", \"detect\": " << jsonNum(detect_ms)
       << ", \"database\": " << jsonNum(db_ms) << ", \"identify\": " << jsonNum(identify_ms)
       << ", \"pattern\": " << jsonNum(r.timing.pattern_ms)
       << ", \"verify\": " << jsonNum(r.timing.verify_ms) << ", \"total\": " << jsonNum(total_ms)
       << "}}";
    std::printf("%s\n", js.str().c_str());
    return kExitOk;
  }

  std::printf("image      %s (%dx%d), %zu stars detected\n", o.image.c_str(), w, h,
              det.stars.size());
  std::printf("database   %s: %zu stars\n", db_source.c_str(), stars.size());
  std::printf("camera     %s (HFOV %.4f deg%s)\n", cam.describe().c_str(),
              rad2deg(cam.horizontalFov()),
              fixed_cam && !o.camera.camera_file.empty() ? "" : ", focal length fitted");
  std::printf("solved     %s + %s, %d hypotheses, %d FOV(s) tried, false-match P %.2e\n",
              r.algorithm.c_str(), o.solver.c_str(), r.hypotheses_tried, fs.fovs_tried,
              r.false_match_probability);
  std::printf("q_ib       [w x y z] = [%.9f %.9f %.9f %.9f]\n", q.w(), q.x(), q.y(), q.z());
  std::printf("boresight  RA %.5f deg  Dec %+.5f deg  roll %.5f deg\n", rad2deg(rdr.ra),
              rad2deg(rdr.dec), rad2deg(rdr.roll));
  std::printf("1-sigma    cross-boresight %.2f arcsec, roll %.2f arcsec\n",
              rad2arcsec(sig.cross_boresight), rad2arcsec(sig.roll));
  std::printf("residual   RMS %.2f arcsec = %.3f px over %zu stars\n", rad2arcsec(r.rms_residual),
              r.rms_residual_px, r.matches.size());
  std::printf("\n  %8s %9s %9s %6s %9s %7s\n", "HIP", "x [px]", "y [px]", "V", "res [\"]",
              "res[px]");
  for (const StarMatch& m : r.matches) {
    const Vec2& px = fs.obs[m.obs_index].px;
    std::printf("  %8u %9.2f %9.2f %6.2f %9.2f %7.3f\n", m.catalog_id, px.x(), px.y(),
                stars[m.star_index].mag, rad2arcsec(m.residual), m.residual_px);
  }
  std::printf("\ntiming [ms]  load %.2f  detect %.2f  database %.2f  identify %.2f "
              "(pattern %.2f, verify %.2f)  total %.2f\n",
              load_ms, detect_ms, db_ms, identify_ms, r.timing.pattern_ms, r.timing.verify_ms,
              total_ms);
  return kExitOk;
}

}  // namespace

void addSolveCommand(CLI::App& root, CommandRun& run_fn) {
  auto* cmd = root.add_subcommand(
      "solve", "Lost-in-space: detect, identify and solve the attitude of one image");
  auto o = std::make_shared<SolveOptions>();
  cmd->add_option("IMAGE", o->image, "PNG, JPEG, TIFF (8/16-bit) or FITS image")->required();
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
  cmd->add_flag("--json", o->json, "Print one JSON object");
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
                  "name, else today)");
  cmd->add_option("--max-stars", o->max_stars, "Brightest stars used to form patterns")
      ->check(CLI::Range(4, 100))
      ->capture_default_str();
  cmd->add_option("--min-sigma-px", o->min_sigma_px,
                  "Floor of the centroid 1-sigma [px]: camera-model error (default 0.5 without a "
                  "camera file, 0.1 with one)");
  cmd->callback([o, &run_fn] { run_fn = [o] { return run(*o); }; });
}

}  // namespace st::app

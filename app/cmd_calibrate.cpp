// `startracker calibrate IMAGE...|DIR -o camera.yaml`: a camera calibration with the stars
// as targets. Every frame is plate-solved (its focal length and distortion fitted on its
// own), then one joint fit (sensors/camera/camera_fit.hpp) estimates fx, fy, cx, cy, k1 and
// k2 from all frames' stars with each frame's attitude a nuisance parameter, and writes the
// OpenCV YAML that --camera reads.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>

#include "app/cli/common_flags.hpp"
#include "app/camera_flags.hpp"
#include "app/cli/validators.hpp"
#include "app/command.hpp"
#include "imageio/image_file.hpp"
#include "solve/solve_epoch.hpp"
#include "common/output_file.hpp"
#include "catalog/database_cache.hpp"
#include "catalog/database_recipe.hpp"
#include "catalog/star_catalog.hpp"
#include "common/conventions.hpp"
#include "common/errors.hpp"
#include "common/log.hpp"
#include "common/progress.hpp"
#include "sensors/detect/star_detector.hpp"
#include "sensors/identify/fov_search.hpp"

namespace st::app {
namespace {

struct CalibrateOptions {
  bool force = false;  ///< replace an existing -o
  std::vector<std::string> inputs;
  std::string output;
  solve::CameraOptions camera;  ///< the start (optional: else a FOV search)
  std::vector<double> fov_range_deg = {5, 30};
  std::string database;
  double epoch = 0;
  double mag_limit = 6.5;
  int radial_terms = 2;
  bool fix_principal_point = false, square_pixels = false;
};

bool isImageName(const std::filesystem::path& p) {
  std::string e = p.extension().string();
  std::transform(e.begin(), e.end(), e.begin(), ::tolower);
  for (const char* x : {".tif", ".tiff", ".png", ".jpg", ".jpeg", ".pgm", ".fits", ".fit", ".fts"})
    if (e == x) return true;
  return false;
}

/// The inputs with every directory replaced by its images (sorted).
std::vector<std::string> imageFiles(const std::vector<std::string>& inputs) {
  std::vector<std::string> out;
  for (const std::string& in : inputs) {
    if (!std::filesystem::is_directory(in)) {
      if (!std::filesystem::is_regular_file(in)) throw InputError(in + ": no such file or directory");
      out.push_back(in);
      continue;
    }
    std::vector<std::string> here;
    for (const auto& e : std::filesystem::directory_iterator(in))
      if (e.is_regular_file() && isImageName(e.path())) here.push_back(e.path().string());
    if (here.empty()) throw InputError(in + ": no images (.tif .png .jpg .pgm .fits) in this folder");
    std::sort(here.begin(), here.end());
    out.insert(out.end(), here.begin(), here.end());
  }
  return out;
}

/// The star database: --database, or built in memory for the widest field searched.
std::shared_ptr<const StarDatabase> database(const CalibrateOptions& o, int w, int h, double epoch) {
  if (!o.database.empty()) return std::make_shared<const StarDatabase>(StarDatabase::load(o.database));
  CameraDatabaseRecipe r;
  const double aspect = o.camera.pixelAspect();
  const CameraModel widest = o.camera.given()
                                 ? o.camera.resolve(w, h)
                                 : CameraModel::fromFov(w, h, deg2rad(o.fov_range_deg[1]), aspect);
  const CameraModel finest =
      o.camera.given() ? widest : CameraModel::fromFov(w, h, deg2rad(o.fov_range_deg[0]), aspect);
  r.diagonal_fov_rad = 2 * widest.halfDiagonalFov() * 1.05;
  r.pixel_scale_rad = finest.pixelScale();
  r.mag_limit = o.mag_limit;
  r.epoch_jyear = epoch;
  return cameraDatabase(r);
}

struct SolvedFrame {
  std::string file;
  FrameStars stars;
  CameraModel camera;  ///< the frame's own sky fit
};

/// Plate-solves one frame: with the camera of an earlier frame (1 % slack) when there is
/// one, else --camera / --fov-deg, else a FOV search.
std::optional<SolvedFrame> solveFrame(const std::string& file, const cv::Mat& image,
                                      const StarDatabase& db, const CalibrateOptions& o,
                                      const std::optional<CameraModel>& known,
                                      StarIdentifier& identifier) {
  const DetectionResult det = detectStars(image);
  // -v: what detection made of the frame, then its brightest blobs (issue 39: an unsolved
  // frame gave nothing to go on outside solve).
  log::debug("%s: %zu stars detected (%d radiation hits, %d blobs rejected), frame PSF %.2f x "
             "%.2f px%s%s",
             file.c_str(), det.stars.size(), det.hits, det.rejected, det.psf_width_x,
             det.psf_width_y, det.reason.empty() ? "" : "; ", det.reason.c_str());
  for (std::size_t i = 0; i < std::min<std::size_t>(det.stars.size(), 10); ++i) {
    const Centroid& c = det.stars[i];
    log::debug("  #%zu at (%.2f, %.2f) px, flux %.0f, SNR %.1f, flags %s", i + 1, c.px.x(), c.px.y(), c.flux,
               c.snr, centroidFlagNames(c.flags).c_str());
  }
  if (!det.reason.empty() || det.stars.size() < 4) {
    log::warn("%s: skipped: too few stars detected (%zu)", file.c_str(), det.stars.size());
    return std::nullopt;
  }
  constexpr double kFloorPx = 0.1;
  FovSearchResult r;
  if (known)
    r = identifyAndFit(det.stars, *known, db, identifier,
                       CameraFitPolicy::approximateFov(0.01, known->pixelAspect()), kFloorPx);
  else if (o.camera.given())
    r = identifyAndFit(det.stars, o.camera.resolve(image.cols, image.rows), db, identifier,
                       o.camera.camera_file.empty()
                           ? CameraFitPolicy::approximateFov(0.01, o.camera.pixelAspect())
                                                    : CameraFitPolicy::cameraFile(o.camera.resolve(image.cols, image.rows)),
                       kFloorPx);
  else
    r = identifyUnknownFov(det.stars, image.cols, image.rows, db, identifier,
                           fovSearchGrid(deg2rad(o.fov_range_deg[0]), deg2rad(o.fov_range_deg[1]), 0.02),
                           0.02, kFloorPx, {}, o.camera.pixelAspect());
  if (!r.result.solved()) {
    log::warn("%s: skipped: not solved: %s", file.c_str(), r.result.reason.c_str());
    return std::nullopt;
  }
  log::debug("%s: identified %zu of its %zu stars (%s), false-match probability %.2g", file.c_str(),
             r.result.matches.size(), det.stars.size(), r.result.algorithm.c_str(),
             r.result.false_match_probability);
  // The calibration weighs each star by its own centroid sigma, not by this frame's
  // model-error term (that is what the calibration removes).
  const auto obs = toStarObservations(det.stars, r.camera, kFloorPx);
  return SolvedFrame{file, frameStarsOf(obs, r.result, db, r.camera), r.camera};
}

CameraFitResult jointFit(const std::vector<SolvedFrame>& solved, const CalibrateOptions& o,
                         std::vector<FrameStars>& frames) {
  for (const SolvedFrame& s : solved) frames.push_back(s.stars);
  // Start: the first frame's focal length, no distortion.
  const CameraModel& c0 = solved.front().camera;
  const CameraModel start(c0.width(), c0.height(), c0.fx(), c0.fy(), c0.cx(), c0.cy());
  CameraFitSpec spec;
  spec.aspect = !o.square_pixels;
  spec.principal_point = !o.fix_principal_point;
  spec.radial_terms = o.radial_terms;
  // A principal-point shift is almost a rotation of each narrow frame: a weak prior at the
  // image centre (5 % of the width) keeps it determined; the stars overrule it where they can.
  const CameraPrior prior = CameraPrior::around(start, 0, 0.05 * start.width(), 0);
  CameraFitOptions fo;
  fo.outlier_sigma = 5;
  return fitCameraChoosingRadial(start, frames, spec, &prior, fo);
}

void printReport(const std::vector<SolvedFrame>& solved, const CameraFitResult& fit,
                 double model_px) {
  std::printf("%-50s %6s %12s %12s\n", "frame", "stars", "before [px]", "after [px]");
  for (std::size_t j = 0; j < solved.size(); ++j)
    std::printf("%-50s %6zu %12.3f %12.3f\n",
                std::filesystem::path(solved[j].file).filename().string().c_str(),
                solved[j].stars.size(), fit.frame_rms_before_px[j], fit.frame_rms_after_px[j]);
  std::printf("all frames: %d stars (%d outliers left out), RMS %.3f -> %.3f px, chi2 %.1f for %d dof, "
              "model error %.3f px\n",
              fit.stars, fit.outliers, fit.rms_before_px, fit.rms_after_px, fit.chi2, fit.dof, model_px);
  const auto line = [&](const char* name, CameraParam p) {
    if (fit.sigma(p) > 0)
      std::printf("  %-3s %14.6f +- %.6f\n", name, fit.theta[p], fit.sigma(p));
    else
      std::printf("  %-3s %14.6f (fixed)\n", name, fit.theta[p]);
  };
  line("fx", kFx), line("fy", kFy), line("cx", kCx), line("cy", kCy), line("k1", kK1), line("k2", kK2);
  std::printf("  radial terms the stars support: %d; HFOV %.4f deg\n", fit.spec.radial_terms,
              rad2deg(fit.camera.horizontalFov()));
  // fx / fy and its 1-sigma from the fit's covariance (first-order propagation).
  if (fit.spec.aspect) {
    const double a = fit.theta[kFx] / fit.theta[kFy];
    const double rx = fit.sigma(kFx) / fit.theta[kFx], ry = fit.sigma(kFy) / fit.theta[kFy];
    const double rho = fit.sigma(kFx) > 0 && fit.sigma(kFy) > 0
                           ? fit.cov(kFx, kFy) / (fit.sigma(kFx) * fit.sigma(kFy)) : 0;
    const double sa = a * std::sqrt(std::max(0.0, rx * rx + ry * ry - 2 * rho * rx * ry));
    const bool departs = std::abs(a - 1) > std::max(3 * sa, 1e-3);
    std::printf("  pixel aspect fx/fy %.5f +- %.5f%s\n", a, sa,
                departs ? ": the pixels are not square on the sky (binned rows or columns, or "
                          "an anamorphic lens); fx and fy are fitted apart"
                        : " (square within the fit)");
  }
}

int runCalibrate(const CalibrateOptions& o) {
  if (o.fov_range_deg.size() != 2 || !(o.fov_range_deg[0] > 0) || o.fov_range_deg[1] < o.fov_range_deg[0])
    throw InputError("--fov-range needs MIN MAX in degrees with 0 < MIN <= MAX");
  const std::vector<std::string> files = imageFiles(o.inputs);
  std::vector<NamedPath> inputs;
  for (const std::string& f : files) inputs.push_back({f, "an input frame"});
  inputs.push_back({o.camera.camera_file, "--camera"});
  inputs.push_back({o.database, "--database"});
  refuseSameFile(o.output, "-o", inputs);
  prepareOutputFile(o.output, "-o", o.force);
  // An unreadable frame is skipped with a warning, as solve does in a batch (issue 39: one
  // damaged file ended the whole calibration); the first readable one sets the size.
  std::vector<std::string> unreadable;
  const auto load = [&](const std::string& f) -> std::optional<imageio::LoadedImage> {
    try {
      return imageio::loadImage(f);
    } catch (const InputError& e) {
      log::warn("%s; skipped", e.what());
      unreadable.push_back(f);
      return std::nullopt;
    }
  };
  std::optional<imageio::LoadedImage> first_loaded;
  std::size_t first_index = 0;
  for (; first_index < files.size() && !first_loaded; ++first_index) first_loaded = load(files[first_index]);
  if (!first_loaded) throw InputError("no readable frame among the " + std::to_string(files.size()) + " given");
  const imageio::LoadedImage first = std::move(*first_loaded);
  const std::string first_file = files[first_index - 1];
  // As solve: --epoch, else the first frame's date, else today (solve/solve_epoch.hpp).
  const solve::SolveEpoch chosen =
      solve::chooseEpoch(o.epoch, first.epoch_jyear, first.epoch_source, nullptr);
  const double epoch = chosen.jyear;
  if (o.epoch <= 0)
    log::info("epoch %.2f (%s%s)", epoch, chosen.source.c_str(),
              first.epoch_jyear ? "" : ": no date in the first frame; give --epoch");
  const std::shared_ptr<const StarDatabase> db_held = database(o, first.image.cols, first.image.rows, epoch);
  const StarDatabase& db = *db_held;
  auto identifier = StarIdentifier::create(StarIdentifier::defaultName());
  std::vector<SolvedFrame> solved;
  std::optional<CameraModel> known;
  ProgressBar bar("solving", files.size());
  for (std::size_t k = first_index - 1; k < files.size(); ++k) {
    const std::string& f = files[k];
    std::optional<imageio::LoadedImage> loaded = k + 1 == first_index ? first : load(f);
    if (!loaded) {
      bar.increment();
      continue;
    }
    const imageio::LoadedImage& img = *loaded;
    if (img.image.cols != first.image.cols || img.image.rows != first.image.rows)
      throw InputError(f + ": " + std::to_string(img.image.cols) + "x" + std::to_string(img.image.rows) +
                       " px, but " + first_file + " is " + std::to_string(first.image.cols) + "x" +
                       std::to_string(first.image.rows) + ": one camera, one image size");
    if (auto s = solveFrame(f, img.image, db, o, known, *identifier)) {
      if (!known) known = s->camera;
      solved.push_back(std::move(*s));
    }
    bar.increment();
  }
  bar.finish();
  if (solved.empty()) {
    log::error("no frame solved: nothing to calibrate from");
    return kExitFailure;
  }
  std::vector<FrameStars> frames;
  const CameraFitResult fit = jointFit(solved, o, frames);
  if (!fit.ok) {
    log::error("calibration failed: %s", fit.reason.c_str());
    return kExitFailure;
  }
  printReport(solved, fit, modelErrorSigmaPx(fit, frames));
  fit.camera.saveYaml(o.output);
  std::printf("wrote %s (%zu of %zu frames solved%s)\n", o.output.c_str(), solved.size(),
              files.size(),
              unreadable.empty() ? ""
                                 : (", " + std::to_string(unreadable.size()) + " unreadable skipped").c_str());
  return kExitOk;
}

}  // namespace

void addCalibrateCommand(CLI::App& root, CommandRun& run) {
  auto* cmd = root.add_subcommand(
      "calibrate", "Calibrate a camera from star frames: fx fy cx cy k1 k2 -> OpenCV YAML");
  auto o = std::make_shared<CalibrateOptions>();
  cmd->add_option("inputs", o->inputs, "Images or folders of images of one camera")->required();
  cmd->add_option("-o,--output", o->output, "Camera file to write (OpenCV YAML, --camera reads it)")
      ->required();
  cli::addForceFlag(*cmd, o->force);
  addCameraFlags(*cmd, o->camera);
  cmd->add_option("--fov-range", o->fov_range_deg, "FOV search range without --camera/--fov-deg [deg]")
      ->expected(2)
      ->capture_default_str();
  cmd->add_option("--database", o->database, "Star database file (default: built in memory)");
  cmd->add_option("--epoch", o->epoch, "Observation epoch, Julian year (default: from the first file's name or DATE-OBS)");
  cmd->add_option("--mag-limit", o->mag_limit, "Faintest stars of the in-memory database [V]")
      ->capture_default_str();
  cmd->add_option("--radial-terms", o->radial_terms, "Radial distortion terms at most (0, 1 or 2; kept only where the stars support them)")
      ->check(CLI::Range(0, 2))
      ->capture_default_str();
  cmd->add_flag("--fix-principal-point", o->fix_principal_point, "Keep cx, cy at the image centre");
  cmd->add_flag("--square-pixels", o->square_pixels, "Keep fy / fx (one focal length)");
  cmd->callback([o, &run] { run = [o] { return runCalibrate(*o); }; });
}

}  // namespace st::app

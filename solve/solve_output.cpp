#include "solve/solve_output.hpp"


#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <mutex>

#include "solve/annotate.hpp"
#include "solve/camera_report.hpp"
#include "common/log.hpp"
#include "common/conventions.hpp"
#include "sensors/identify/photometry.hpp"

#include <Eigen/Eigenvalues>

namespace st::solve {

std::string catalogIdLabel(const std::string& catalog_name) {
  if (catalog_name.rfind("Hipparcos", 0) == 0) return "HIP";
  if (catalog_name.find("Bright Star") != std::string::npos) return "HR";
  if (catalog_name.find("Tycho") != std::string::npos) return "TYC";
  return "ID";
}

namespace {

std::string idLabel(const SolveReport& r) { return catalogIdLabel(r.db.report().catalog_name); }

/// Matched star k's pixel in the input (the un-mirrored obs pixel of a flipped solution is
/// not where the star is in the image).
const Vec2& inputPixel(const SolveReport& r, const StarMatch& m) { return r.in.stars[m.obs_index].px; }

/// B-V by catalog id from the catalog the database was built from (the database keeps only
/// V), read once per path; empty when that file cannot be read (a database built elsewhere).
const std::map<uint32_t, double>& colourIndex(const std::string& catalog_path) {
  static std::mutex mutex;
  static std::map<std::string, std::map<uint32_t, double>> by_path;
  const std::lock_guard<std::mutex> lock(mutex);
  auto it = by_path.find(catalog_path);
  if (it != by_path.end()) return it->second;
  std::map<uint32_t, double>& m = by_path[catalog_path];
  try {
    for (const CatalogEntry& e : loadCatalog(catalog_path).entries)
      if (std::isfinite(e.bv)) m[e.id] = e.bv;
  } catch (const std::exception& e) {
    log::info("photometry: no B-V colours (%s): no colour term", e.what());
  }
  return m;
}

struct Photometry {
  std::vector<PhotometryStar> stars;
  PhotometryFit fit;
};

/// The exposure of an input is not known to solve: 1 s, so the zero point holds it
/// (ZP = ZP_1s + 2.5 log10 t for a frame of exposure t).
constexpr double kAssumedExposureS = 1.0;

/// True when the database holds its stars' colours (format 4 on; older files: none).
bool hasColours(const StarDatabase& db) {
  for (const Star& s : db.stars())
    if (std::isfinite(s.bv)) return true;
  return false;
}

Photometry photometry(const SolveReport& r) {
  // B-V by catalog id: the database's own (format 4), else the catalog it was built from.
  std::map<uint32_t, double> own;
  if (hasColours(r.db))
    // The catalog's B-V has at most 4 decimals: rounded back from the file's float, it is the
    // catalog's own double again (what an older database's catalog read gives).
    for (const StarMatch& m : r.ps.search.result.matches)
      own.emplace(m.catalog_id, std::round(double(r.db.stars()[m.star_index].bv) * 1e4) / 1e4);
  const std::map<uint32_t, double>& bv = own.empty() ? colourIndex(r.db.report().catalog_path) : own;
  Photometry p;
  p.stars = photometryStars(r.in.stars, r.ps.search.obs, r.ps.search.result.matches, r.db,
                            kAssumedExposureS, [&bv](uint32_t id) {
                              const auto it = bv.find(id);
                              return it == bv.end() ? std::nan("") : it->second;
                            });
  p.fit = fitPhotometry(p.stars);
  return p;
}

/// null for NaN (JSON has no NaN).
nlohmann::ordered_json number(double v) {
  return std::isfinite(v) ? nlohmann::ordered_json(v) : nullptr;
}

nlohmann::ordered_json photometryJson(const Photometry& p) {
  const PhotometryFit& f = p.fit;
  if (!f.ok) return {{"fitted", false}, {"reason", f.reason}};
  return {{"fitted", true},
          {"exposure_s", kAssumedExposureS},
          {"zero_point", f.zero_point},
          {"zero_point_se", f.zero_point_se},
          {"colour_term", f.colour_fitted ? number(f.colour_term) : nullptr},
          {"colour_term_se", f.colour_fitted ? number(f.colour_term_se) : nullptr},
          {"off_axis_exponent", f.off_axis_exponent},
          {"off_axis_exponent_fitted", f.off_axis_fitted},
          {"off_axis_exponent_se", f.off_axis_fitted ? number(f.off_axis_se) : nullptr},
          {"scatter_mag", f.scatter},
          {"robust_sigma_mag", f.robust_sigma},
          {"stars_used", f.used},
          {"stars_clipped", f.clipped}};
}

nlohmann::ordered_json starsJson(const SolveReport& r, const Photometry& p) {
  nlohmann::ordered_json stars = nlohmann::ordered_json::array();
  const std::string label = idLabel(r);
  const auto& matches = r.ps.search.result.matches;
  for (std::size_t k = 0; k < matches.size(); ++k) {
    const StarMatch& m = matches[k];
    const Vec2& px = inputPixel(r, m);
    stars.push_back({{"id", m.catalog_id},
                     {"name", label + " " + std::to_string(m.catalog_id)},
                     {"x", px.x()},
                     {"y", px.y()},
                     {"mag", r.db.stars()[m.star_index].mag},
                     {"bv", number(p.stars[k].bv)},
                     {"mag_inst", number(p.stars[k].m_inst)},
                     {"mag_fitted", number(p.fit.fitted[k])},
                     {"mag_residual", number(p.fit.residual[k])},
                     {"photometry_used", bool(p.fit.kept[k])},
                     {"residual_arcsec", rad2arcsec(m.residual)},
                     {"residual_px", m.residual_px}});
  }
  return stars;
}

}  // namespace

/// RA/Dec [rad] of the image's centre pixel ((w-1)/2, (h-1)/2): the boresight is the
/// principal point's direction, which a calibrated camera puts elsewhere. The centre is its
/// own mirror image, so a flipped solution's un-mirrored camera gives it too.
/// What detection made of the frame (an image's; zeros for a star list).
static nlohmann::ordered_json detectionJson(const SolveReport& r) {
  return {{"radiation_hits", r.in.hits},
          {"rejected_blobs", r.in.rejected.size()},
          {"psf_width_px", {r.in.psf_width_x, r.in.psf_width_y}}};
}

static void imageCentreRaDec(const SolveReport& r, double& ra, double& dec) {
  const CameraModel& cam = r.ps.search.camera;
  const Vec2 centre(0.5 * (r.in.width - 1), 0.5 * (r.in.height - 1));
  raDecFromVector(r.ps.search.result.q_ic * cam.pixelToVector(centre), ra, dec);
}

nlohmann::ordered_json solutionJson(const SolveReport& r) {
  const IdentifyResult& res = r.ps.search.result;
  const RaDecRoll rdr = raDecRollFromAttitude(res.q_ic);
  double centre_ra = 0, centre_dec = 0;
  imageCentreRaDec(r, centre_ra, centre_dec);
  const AttitudeSigma sig = attitudeSigma(res.cov_cam);
  const Quat q = canonical(res.q_ic);  // no mounting: the body frame is the camera frame
  nlohmann::ordered_json cov = nlohmann::ordered_json::array();
  for (int i = 0; i < 3; ++i)
    cov.push_back({res.cov_cam(i, 0), res.cov_cam(i, 1), res.cov_cam(i, 2)});
  nlohmann::ordered_json j = {
      {"solved", true}, {"image", r.o.input}, {"input", r.in.star_list ? "star list" : "image"},
      {"parity", toString(r.ps.parity)}, {"ra_deg", rad2deg(rdr.ra)}, {"dec_deg", rad2deg(rdr.dec)},
      {"roll_deg", rad2deg(rdr.roll)}, {"centre_ra_deg", rad2deg(centre_ra)},
      {"centre_dec_deg", rad2deg(centre_dec)}, {"q_ib", {q.w(), q.x(), q.y(), q.z()}}, {"covariance", cov},
      {"sigma_cross_boresight_arcsec", rad2arcsec(sig.cross_boresight)},
      {"sigma_roll_arcsec", rad2arcsec(sig.roll)},
      {"hfov_deg", rad2deg(r.ps.search.camera.horizontalFov())}, {"algorithm", res.algorithm},
      {"solver", r.o.solver}, {"stars_detected", r.in.stars.size()},
      {"stars_matched", res.matches.size()}, {"rms_residual_arcsec", rad2arcsec(res.rms_residual)},
      {"rms_residual_px", res.rms_residual_px},
      {"false_match_probability", res.false_match_probability},
      {"hypotheses_tried", res.hypotheses_tried}, {"fovs_tried", r.ps.search.fovs_tried},
      {"epoch_jyear", r.epoch.jyear}, {"epoch_source", r.epoch.source},
      {"database", r.db_source}, {"database_epoch_jyear", r.db.params().epoch_jyear},
      {"catalog", r.db.report().catalog_name}, {"catalog_id", idLabel(r)}};
  j["frame"] = r.frame.name();
  const Vec3 v = r.frame.velocity(r.epoch.jyear);
  j["aberration_velocity_km_s"] = {v.x(), v.y(), v.z()};
  j["camera"] = cameraJson(r);
  j["detection"] = detectionJson(r);
  // The residuals against the centroids' own sigmas (model-error term included): chi-square
  // with 2n - 3 degrees of freedom when the covariances are honest (clipped stars too).
  double chi2 = 0;
  for (const StarMatch& m : res.matches) {
    const double s = r.ps.search.obs[m.obs_index].sigma;
    chi2 += s > 0 ? (m.residual / s) * (m.residual / s) : 0;
  }
  j["residual_chi2"] = chi2;
  j["residual_dof"] = 2 * static_cast<int>(res.matches.size()) - 3;
  const Photometry phot = photometry(r);
  j["photometry"] = photometryJson(phot);
  j["stars"] = starsJson(r, phot);
  j["timing_ms"] = {{"load", r.ms.load},         {"detect", r.ms.detect},
                    {"database", r.ms.database}, {"identify", r.ms.identify},
                    {"pattern", res.timing.pattern_ms}, {"verify", res.timing.verify_ms},
                    {"total", r.ms.total}};
  return j;
}

nlohmann::ordered_json failureJson(const SolveReport& r) {
  const IdentifyResult& res = r.ps.search.result;
  nlohmann::ordered_json j = {{"solved", false},
                              {"status", res.solved() ? "error" : toString(res.status)},
                              {"reason", r.failure},
                              {"image", r.o.input},
                              {"stars_detected", r.in.stars.size()},
                              {"parities_tried", r.ps.parities_tried},
                              {"cpu_limit_reached", r.ps.search.cpu_limit_reached}};
  j["detection"] = detectionJson(r);
  j["exit_code"] = 1;
  return j;
}

nlohmann::ordered_json errorJson(const std::string& message, int exit_code) {
  // The command line's error object (app/cli/json_error.hpp builds it here), with solve's
  // own two keys first.
  return {{"solved", false}, {"status", "error"}, {"error", message}, {"exit_code", exit_code}};
}

std::string jsonLine(const nlohmann::ordered_json& j) {
  // Invalid UTF-8 in a file name must not abort the one line a script waits for.
  return j.dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace);
}

void printJson(const nlohmann::ordered_json& j) {
  std::printf("%s\n", jsonLine(j).c_str());
  std::fflush(stdout);
}

void printDetections(const FrameInput& in, std::size_t n) {
  std::fprintf(stderr, "  %3s %8s %8s %9s %7s %7s %5s %6s %6s %6s  %s\n", "#", "x [px]",
               "y [px]", "flux", "peak", "SNR", "area", "s_maj", "s_min", "pk/flx", "flags");
  for (std::size_t i = 0; i < in.stars.size(); ++i) {
    const Centroid& c = in.stars[i];
    // The brightest n, and every radiation hit (ranked last) with why it is one.
    if (i >= n && !(c.flags & kRadiationHit)) continue;
    // Sigma of the light along and across its long axis, from the blob's second moments.
    const Eigen::SelfAdjointEigenSolver<Mat2> es(c.shape);
    const double lo = std::sqrt(std::max(es.eigenvalues()(0), 0.0));
    const double hi = std::sqrt(std::max(es.eigenvalues()(1), 0.0));
    std::fprintf(stderr, "  %3zu %8.2f %8.2f %9.1f %7.1f %7.1f %5d %6.2f %6.2f %6.3f  %s\n", i,
                 c.px.x(), c.px.y(), c.flux, c.peak, c.snr, c.area, hi, lo,
                 c.flux > 0 ? c.peak / c.flux : 0.0, centroidFlagNames(c.flags).c_str());
  }
  if (in.stars.size() > n)
    std::fprintf(stderr, "  (%zu more not shown)\n",
                 in.stars.size() - n - static_cast<std::size_t>(std::max(0, in.hits)));
}

void printSolutionText(const SolveReport& r) {
  const IdentifyResult& res = r.ps.search.result;
  const CameraModel& cam = r.ps.search.camera;
  const RaDecRoll rdr = raDecRollFromAttitude(res.q_ic);
  const AttitudeSigma sig = attitudeSigma(res.cov_cam);
  const Quat q = canonical(res.q_ic);
  std::printf("%-10s %s (%dx%d), %zu stars %s\n", r.in.star_list ? "star list" : "image",
              r.o.input.c_str(), r.in.width, r.in.height, r.in.stars.size(),
              r.in.star_list ? "listed" : "detected");
  std::printf("database   %s: %zu stars, epoch %.2f, %s\n", r.db_source.c_str(),
              r.db.stars().size(), r.db.params().epoch_jyear, r.db.report().catalog_name.c_str());
  std::printf("camera     %s (HFOV %.4f deg%s)\n", cam.describe().c_str(),
              rad2deg(cam.horizontalFov()), r.focal_fitted ? ", focal length fitted" : "");
  printCameraFitText(r);
  // FOVs are tried only in a search without a camera; with one the count says nothing.
  const std::string fovs =
      r.ps.search.fovs_tried > 0 ? ", " + std::to_string(r.ps.search.fovs_tried) + " FOVs tried" : "";
  std::printf("solved     %s + %s, %d hypotheses%s, false-match P %.2e\n", res.algorithm.c_str(),
              r.o.solver.c_str(), res.hypotheses_tried, fovs.c_str(), res.false_match_probability);
  std::printf("parity     %s%s\n", toString(r.ps.parity),
              r.ps.parity == Parity::Flipped ? " (image mirrored left-right; the attitude is "
                                               "the un-mirrored camera's)"
                                             : "");
  std::printf("q_ib       [w x y z] = [%.9f %.9f %.9f %.9f]\n", q.w(), q.x(), q.y(), q.z());
  std::printf("frame      %s\n", r.frame.describe(r.epoch.jyear).c_str());
  std::printf("boresight  RA %.5f deg  Dec %+.5f deg  roll %.5f deg\n", rad2deg(rdr.ra),
              rad2deg(rdr.dec), rad2deg(rdr.roll));
  double centre_ra = 0, centre_dec = 0;
  imageCentreRaDec(r, centre_ra, centre_dec);
  std::printf("centre     RA %.5f deg  Dec %+.5f deg (the image's centre pixel)\n",
              rad2deg(centre_ra), rad2deg(centre_dec));
  std::printf("1-sigma    cross-boresight %.2f arcsec, roll %.2f arcsec\n",
              rad2arcsec(sig.cross_boresight), rad2arcsec(sig.roll));
  std::printf("residual   RMS %.2f arcsec = %.3f px over %zu stars\n", rad2arcsec(res.rms_residual),
              res.rms_residual_px, res.matches.size());
  const Photometry phot = photometry(r);
  const PhotometryFit& pf = phot.fit;
  char colour[64] = "(no colour term)";
  if (pf.colour_fitted)
    std::snprintf(colour, sizeof colour, "%+.3f (+-%.3f) (B-V)", pf.colour_term, pf.colour_term_se);
  if (pf.ok)
    std::printf("photometry V = m_inst + %.3f (+-%.3f) %s, off-axis cos^%.2f%s; scatter %.3f mag "
                "over %d stars (%d clipped); m_inst for t = 1 s\n",
                pf.zero_point, pf.zero_point_se, colour, pf.off_axis_exponent,
                pf.off_axis_fitted ? " (fitted)" : " (fixed)", pf.scatter, pf.used, pf.clipped);
  else
    std::printf("photometry not fitted: %s\n", pf.reason.c_str());
  std::printf("\n  %8s %9s %9s %6s %6s %6s %9s %7s\n", idLabel(r).c_str(), "x [px]", "y [px]", "V",
              "V fit", "dV", "res [\"]", "res[px]");
  for (std::size_t k = 0; k < res.matches.size(); ++k) {
    const StarMatch& m = res.matches[k];
    const Vec2& px = inputPixel(r, m);
    std::printf("  %8u %9.2f %9.2f %6.2f %6.2f %6.2f %9.2f %7.3f\n", m.catalog_id, px.x(), px.y(),
                r.db.stars()[m.star_index].mag, pf.fitted[k], pf.residual[k],
                rad2arcsec(m.residual), m.residual_px);
  }
  std::printf("\ntiming [ms]  load %.2f  detect %.2f  database %.2f  identify %.2f "
              "(pattern %.2f, verify %.2f)  total %.2f\n",
              r.ms.load, r.ms.detect, r.ms.database, r.ms.identify, res.timing.pattern_ms,
              res.timing.verify_ms, r.ms.total);
  std::fflush(stdout);
}

void writeSolveAnnotation(const SolveReport& r, const std::string& path) {
  const IdentifyResult& res = r.ps.search.result;
  const bool solved = r.failure.empty();
  std::vector<MarkedBlob> blobs;
  for (const Centroid& c : r.in.stars)
    blobs.push_back({c.px, (c.flags & kRadiationHit)                ? BlobKind::kHit
                           : (c.flags & (kDiffuse | kElongated))   ? BlobKind::kDiffuse
                                                                   : BlobKind::kStar});
  for (const DetectionResult::Rejected& b : r.in.rejected) blobs.push_back({b.px, BlobKind::kRejected});
  std::vector<LabelledStar> identified;
  const std::string label = idLabel(r);
  if (solved)
    for (const StarMatch& m : res.matches)
      identified.push_back({inputPixel(r, m), label + " " + std::to_string(m.catalog_id)});
  std::vector<std::string> caption;
  char line[200];
  if (solved) {
    const RaDecRoll rdr = raDecRollFromAttitude(res.q_ic);
    const AttitudeSigma sig = attitudeSigma(res.cov_cam);
    std::snprintf(line, sizeof line, "RA %.4f  Dec %+.4f  roll %.3f deg%s", rad2deg(rdr.ra),
                  rad2deg(rdr.dec), rad2deg(rdr.roll),
                  r.ps.parity == Parity::Flipped ? "  (flipped parity)" : "");
    caption.push_back(line);
    std::snprintf(line, sizeof line,
                  "1-sigma %.1f\" cross-boresight, %.1f\" roll; %zu/%zu stars, RMS %.2f px",
                  rad2arcsec(sig.cross_boresight), rad2arcsec(sig.roll), res.matches.size(),
                  r.in.stars.size(), res.rms_residual_px);
    caption.push_back(line);
  } else {
    // Why the solve stopped, cut into lines that fit the picture.
    const std::string why = "not solved: " + r.failure;
    const std::size_t width = static_cast<std::size_t>(std::max(40, r.in.width / 8));
    for (std::size_t i = 0; i < why.size() && caption.size() < 6; i += width)
      caption.push_back(why.substr(i, width));
  }
  int kinds[4] = {0, 0, 0, 0};
  for (const MarkedBlob& b : blobs) ++kinds[static_cast<int>(b.kind)];
  std::snprintf(line, sizeof line,
                "blobs: %d stars (orange), %d radiation hits (magenta x), %d diffuse (yellow), "
                "%d rejected (grey)",
                kinds[0], kinds[1], kinds[2], kinds[3]);
  caption.push_back(line);
  const cv::Mat canvas =
      r.in.image.empty() ? cv::Mat::zeros(r.in.height, r.in.width, CV_8UC1) : r.in.image;
  // The fitted camera's, else the one detection used (the camera file is not read again).
  const double aspect = solved ? r.ps.search.camera.pixelAspect() : r.in.pixel_aspect;
  writeAnnotatedFrame(path, canvas, blobs, identified, caption, aspect);
}

}  // namespace st::solve

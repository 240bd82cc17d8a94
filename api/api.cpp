// The façade's small pieces: version, data folder, Database, the tracker and its JSON.
#include <filesystem>

#include "api/shared_cache.hpp"
#include "catalog/database_recipe.hpp"
#include "solve/solve_epoch.hpp"
#include "common/check.hpp"
#include "include/startracker/startracker.hpp"

namespace st::api {

std::string version() { return ST_VERSION; }

std::string dataDir() {
  return std::filesystem::path(StarDatabase::defaultCatalogPath()).parent_path().string();
}

Database::Database(std::shared_ptr<const StarDatabase> db, std::string source, bool from_file)
    : db_(std::move(db)), source_(std::move(source)), from_file_(from_file) {
  ST_ASSERT(db_ != nullptr);
}

Database Database::load(const std::string& path) {
  return Database(std::make_shared<const StarDatabase>(StarDatabase::load(path)), path, true);
}

std::shared_ptr<solve::DatabaseCache> sharedDatabaseCache(bool no_cache) {
  static const auto disk =
      std::make_shared<solve::DatabaseCache>(StarDatabase::defaultCatalogPath(), true);
  static const auto memory =
      std::make_shared<solve::DatabaseCache>(StarDatabase::defaultCatalogPath(), false);
  return no_cache ? memory : disk;
}

Database Database::forCamera(const CameraModel& camera, double mag_limit, double epoch_jyear) {
  const double epoch = solve::chooseEpoch(epoch_jyear, std::nullopt, "", nullptr).jyear;
  // The recipe every command uses (catalog/database_recipe.hpp), in the apparent frame.
  CameraDatabaseRecipe r;
  r.diagonal_fov_rad = 2 * camera.halfDiagonalFov();
  r.pixel_scale_rad = camera.pixelScale();
  r.mag_limit = mag_limit;
  r.epoch_jyear = epoch;
  r.aberration = true;
  solve::CachedDatabase c = sharedDatabaseCache()->get(databaseParams(r));
  return Database(c.db, c.how + " from " + StarDatabase::defaultCatalogPath(), false);
}

nlohmann::ordered_json frameResultJson(const FrameResult& r) {
  nlohmann::ordered_json j = {{"mode", toString(r.mode)},
                              {"has_attitude", r.hasAttitude()},
                              {"failure", toString(r.failure)},
                              {"detail", r.detail},
                              {"prediction", toString(r.prediction)},
                              {"fell_back_to_lost_in_space", r.fell_back_to_lost_in_space},
                              {"num_blobs", r.num_blobs}};
  if (r.hasAttitude()) {
    const Quat q = canonical(r.q_ib);
    const RaDecRoll rdr = raDecRollFromAttitude(q);
    const AttitudeSigma sig = attitudeSigma(r.cov_body);
    nlohmann::ordered_json cov = nlohmann::ordered_json::array();
    for (int i = 0; i < 3; ++i) cov.push_back({r.cov_body(i, 0), r.cov_body(i, 1), r.cov_body(i, 2)});
    j["q_ib"] = {q.w(), q.x(), q.y(), q.z()};
    j["ra_deg"] = rad2deg(rdr.ra);
    j["dec_deg"] = rad2deg(rdr.dec);
    j["roll_deg"] = rad2deg(rdr.roll);
    j["covariance"] = cov;
    j["sigma_cross_boresight_arcsec"] = rad2arcsec(sig.cross_boresight);
    j["sigma_roll_arcsec"] = rad2arcsec(sig.roll);
  }
  nlohmann::ordered_json stars = nlohmann::ordered_json::array();
  for (const MatchedStar& s : r.stars)
    stars.push_back({{"id", s.catalog_id}, {"x", s.px.x()}, {"y", s.px.y()},
                     {"residual_arcsec", rad2arcsec(s.residual)}});
  j["stars"] = stars;
  j["timing_ms"] = {{"detect", 1e3 * r.timings.detect},
                    {"identify", 1e3 * r.timings.identify},
                    {"attitude", 1e3 * r.timings.attitude},
                    {"total", 1e3 * r.timings.total}};
  return j;
}

Tracker::Tracker(const CameraModel& camera, TrackerOptions options, std::optional<Database> db)
    : db_(db ? std::move(*db) : Database::forCamera(camera)) {
  options.validate();
  tracker_ = std::make_unique<StarTracker>(db_.stars(), camera, std::move(options));
}

Tracker::~Tracker() = default;

FrameResult Tracker::process(const cv::Mat& image, double t_s, const FrameInputs& in) {
  if (image.empty() || (image.type() != CV_8UC1 && image.type() != CV_16UC1))
    throw InputError("image: not an 8- or 16-bit single-channel grey image");
  if (image.cols != tracker_->camera().width() || image.rows != tracker_->camera().height())
    throw InputError("image: " + std::to_string(image.cols) + "x" + std::to_string(image.rows) +
                     " px, the tracker's camera is " + std::to_string(tracker_->camera().width()) +
                     "x" + std::to_string(tracker_->camera().height()));
  if (const std::optional<double> seen = frozen_.repeats(image, t_s))
    return frozenFrameResult(*seen);  // a repeated readout (frozen_frame.hpp)
  return tracker_->process(image, t_s, in);
}

void Tracker::reset() {
  tracker_->reset();
  frozen_.reset();
}

}  // namespace st::api

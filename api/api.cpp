// The façade's small pieces: version, data folder, Database, the tracker and its JSON.
#include <filesystem>

#include "catalog/database_cache.hpp"
#include "catalog/database_recipe.hpp"
#include "solve/solve_epoch.hpp"
#include "common/check.hpp"
#include "sensors/tracking/frozen_frame.hpp"
#include "sensors/tracking/star_tracker.hpp"
#include "sensors/tracking/tracker_options.hpp"
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

Database Database::forCamera(const CameraModel& camera, double mag_limit, double epoch_jyear) {
  const double epoch = solve::chooseEpoch(epoch_jyear, std::nullopt, "", nullptr).jyear;
  // The recipe every command uses (catalog/database_recipe.hpp), in the apparent frame.
  CameraDatabaseRecipe r;
  r.diagonal_fov_rad = 2 * camera.halfDiagonalFov();
  r.pixel_scale_rad = camera.pixelScale();
  r.mag_limit = mag_limit;
  r.epoch_jyear = epoch;
  r.aberration = true;
  std::string how;
  std::shared_ptr<const StarDatabase> db = cameraDatabase(r, "", true, &how);
  return Database(std::move(db), how + " from " + StarDatabase::defaultCatalogPath(), false);
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

struct Tracker::Impl {
  Database db;
  std::unique_ptr<StarTracker> tracker;
  FrozenFrameCheck frozen;
};

namespace {
TrackerOptions optionsOf(const TrackerSettings& s) {
  TrackerOptions o;
  if (!std::isnan(s.min_sigma_px)) o.min_sigma_px = s.min_sigma_px;
  if (!std::isnan(s.tracking_min_sigma_px)) o.tracking_min_sigma_px = s.tracking_min_sigma_px;
  o.R_body_cam = s.R_body_cam;
  return o;
}
}  // namespace

Tracker::Tracker(const CameraModel& camera, const TrackerSettings& settings,
                 std::optional<Database> db)
    : Tracker(camera, optionsOf(settings), std::move(db)) {}

Tracker::Tracker(const CameraModel& camera, const TrackerOptions& options,
                 std::optional<Database> db)
    : impl_(new Impl{db ? std::move(*db) : Database::forCamera(camera), nullptr, {}}) {
  TrackerOptions o = options;
  o.validate();
  impl_->tracker = std::make_unique<StarTracker>(impl_->db.stars(), camera, std::move(o));
}

Tracker::~Tracker() = default;
Tracker::Tracker(Tracker&&) noexcept = default;
Tracker& Tracker::operator=(Tracker&&) noexcept = default;

StarTracker& Tracker::tracker() { return *impl_->tracker; }
const Database& Tracker::database() const { return impl_->db; }

FrameResult Tracker::process(const cv::Mat& image, double t_s, const FrameInputs& in) {
  StarTracker& t = *impl_->tracker;
  if (image.empty() || (image.type() != CV_8UC1 && image.type() != CV_16UC1))
    throw InputError("image: not an 8- or 16-bit single-channel grey image");
  if (image.cols != t.camera().width() || image.rows != t.camera().height())
    throw InputError("image: " + std::to_string(image.cols) + "x" + std::to_string(image.rows) +
                     " px, the tracker's camera is " + std::to_string(t.camera().width()) + "x" +
                     std::to_string(t.camera().height()));
  return processFrame(t, impl_->frozen, image, t_s, in);  // frozen_frame.hpp
}

void Tracker::reset() {
  impl_->tracker->reset();
  impl_->frozen.reset();
}

}  // namespace st::api

/// @file startracker.hpp
/// The public C++ API of the star tracker: the one header a program that links the installed
/// library includes (`find_package(startracker)`, target `startracker::api`; or pkg-config
/// `startracker`). A thin façade over the project's stages (api/*.cpp). It includes only the
/// seam types it names, installed beside it (attitude, conventions, errors, camera_model,
/// frame: one definition each, which the stages use too), OpenCV's core, Eigen and
/// nlohmann/json: no MRPT, CLI11 or stage header, and the libraries link no MRPT.
///
///   st::api::SolveOptions o;  o.fov_deg = 11.4;
///   st::api::SolveResult r = st::api::solve(cv::imread(path, cv::IMREAD_UNCHANGED), o);
///   if (r.solved) use(r.ra_deg, r.dec_deg, r.roll_deg, r.q_ib, r.covariance);
///   std::cout << r.json.dump();  // the object `startracker solve --json` prints
///
///   st::api::Tracker t(st::CameraModel::fromFov(1024, 768, st::deg2rad(11.4)));
///   st::FrameInputs in;  in.rate_body = gyro_rate;        // optional
///   in.observer_velocity_km_s = v_orbit;  // optional: corrects the orbit's aberration (5")
///   st::FrameResult fix = t.process(image, t_s, in);     // per frame, in time order
///
/// In-tree, the fusion loop (fusion/fusion_loop.hpp) takes the tracker as its frame processor:
///   st::FusionLoop loop(st::FusionOptions{});
///   loop.setFrameProcessor([&](uint64_t tag, double t, const st::FrameInputs& in) {
///     return t.process(frames[tag], t, in); });
///   loop.setStepCallback([](const st::FusionStep& s) { use(s.filter.q_ib); });
///   loop.pushGyro(t_gyro, rate);  loop.pushFrame(t_frame, tag);  ...  loop.flush();
///   loop.pushVelocity(t_v, v_orbit_km_s);  // optional: every frame then gets the newest
///
/// Conventions (common/conventions.hpp): q_ib is Hamilton, scalar first, v_inertial =
/// R(q_ib) v_body (ICRS); covariances are 3x3 of the body-frame rotation error in rad^2;
/// the camera frame is +z boresight, +x columns, +y rows. Errors of bad input throw
/// st::InputError (common/errors.hpp) naming the value; an image that does not solve is a
/// result (solved = false, with status and reason), not an exception.
#pragma once
#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>

// Only the public seam types, beside this header when installed: no MRPT, CLI11 or stage header.
#include "startracker/attitude.hpp"
#include "startracker/camera_model.hpp"
#include "startracker/conventions.hpp"
#include "startracker/errors.hpp"
#include "startracker/frame.hpp"

namespace st {
class StarDatabase;     // catalog/star_database.hpp: opaque here
class StarTracker;      // sensors/tracking/star_tracker.hpp: opaque here
struct TrackerOptions;  // sensors/tracking/tracker_options.hpp: every tunable, for in-tree code
}  // namespace st

namespace st::api {

/// The library's version ("0.1.0").
std::string version();

/// The folder the default catalog is read from: $STARTRACKER_DATA_DIR when set, else
/// <executable>/../share/startracker when it holds the catalog (an installed tree or an
/// extracted .deb), else the source tree's catalog/data.
std::string dataDir();

/// A star database, shared (cheap to copy). Either loaded from a `startracker catalog build`
/// file, or built in memory from the default catalog with the recipe every command uses
/// (catalog/database_recipe.hpp) for a camera.
class Database {
 public:
  /// Throws InputError naming the file.
  static Database load(const std::string& path);
  /// For `camera` at epoch `epoch_jyear` (Julian year; 0 = today), stars to V <= mag_limit.
  static Database forCamera(const CameraModel& camera, double mag_limit = 6.6,
                            double epoch_jyear = 0);

  const StarDatabase& stars() const { return *db_; }
  const std::shared_ptr<const StarDatabase>& shared() const { return db_; }
  /// The file it came from, or how it was built.
  const std::string& source() const { return source_; }
  /// True when it was read from a file (solve then checks the image epoch against it).
  bool fromFile() const { return from_file_; }

  Database(std::shared_ptr<const StarDatabase> db, std::string source, bool from_file);

 private:
  std::shared_ptr<const StarDatabase> db_;
  std::string source_;
  bool from_file_ = false;
};

/// The options of `startracker solve` that apply to an image in memory.
struct SolveOptions {
  std::optional<double> fov_deg;       ///< horizontal FOV; none (and no camera_file) = search
  std::string camera_file;             ///< calibrated camera (OpenCV YAML/XML, MRPT .ini)
  std::string camera_section = "CAMERA";
  /// A pixel's height over its width on the sky (2 for rows binned 2x), for a camera from
  /// fov_deg or the FOV search; none = square pixels (a camera file states its own).
  std::optional<double> pixel_aspect;
  double fov_min_deg = 5, fov_max_deg = 30;  ///< the FOV search range
  std::string algorithm;               ///< lost-in-space identifier ("" = the default)
  std::string solver;                  ///< Wahba solver ("" = the default)
  double mag_limit = 6.6;              ///< of a database built in memory
  std::optional<double> epoch_jyear;   ///< observation epoch; none = the image's, else today
  bool no_aberration = false;          ///< astrometric (ICRS, as astrometry.net) instead of apparent
  std::vector<double> observer_velocity_km_s;  ///< 3 values [km/s], added to the Earth's
  bool no_cache = false;               ///< never read or write the disk cache of databases
  int max_stars = 12;                  ///< brightest stars the identifier uses
  std::optional<double> min_sigma_px;  ///< centroid sigma floor (default as `solve`)
  std::string parity = "both";         ///< "normal", "flipped" or "both"
  double ra_deg = NAN, dec_deg = NAN, radius_deg = NAN;  ///< position hint (all or none)
  double cpulimit_s = 0;               ///< 0 = no limit
  std::string name = "<memory>";       ///< what the result's "image" field says
  int width = 0, height = 0;           ///< image size of a star list given to solveFile
};

struct SolveResult {
  bool solved = false;
  /// Exactly the object `startracker solve --json` prints for this frame (solved or not;
  /// schema in app/solve/solve_output.hpp).
  nlohmann::ordered_json json;
  Quat q_ib = Quat::Identity();  ///< camera = body
  Mat3 covariance = Mat3::Zero();  ///< [rad^2] camera frame
  double ra_deg = NAN, dec_deg = NAN, roll_deg = NAN;
};

/// Lost-in-space on one 8- or 16-bit grey image (no copy is made; `image` must stay valid
/// during the call). Without `db` a database is built for the camera (or the FOV search) and
/// kept for the next call with the same camera, size and limit while its epoch fits.
/// Throws InputError for a bad image type or size, option or camera file.
SolveResult solve(const cv::Mat& image, const SolveOptions& options = {},
                  const Database* db = nullptr);
/// The same on a caller's buffer (`type` CV_8UC1 or CV_16UC1; `step_bytes` 0 = packed rows).
SolveResult solve(const void* data, int width, int height, int type, std::size_t step_bytes,
                  const SolveOptions& options = {}, const Database* db = nullptr);
/// The same on an image file (PNG, JPEG, TIFF, FITS), or a star list (CSV x,y[,flux] or a FITS
/// table, with `width` and `height`): its epoch comes from DATE-OBS or a date in the file
/// name, as for `startracker solve FILE`.
SolveResult solveFile(const std::string& path, SolveOptions options = {},
                      const Database* db = nullptr);

/// A FrameResult as JSON (mode, failure, detail, q_ib, ra/dec/roll, covariance, stars,
/// timings): what the Python module's Tracker returns.
nlohmann::ordered_json frameResultJson(const FrameResult& r);

/// What a facade user tunes of the tracker; everything else keeps the library's defaults
/// (in-tree code passes the whole TrackerOptions).
struct TrackerSettings {
  /// Floors of the centroid 1-sigma [px] in lost-in-space and in tracking: an uncalibrated
  /// lens needs ~0.5 px (what solve uses without a camera file); NaN = the default.
  double min_sigma_px = NAN, tracking_min_sigma_px = NAN;
  /// Camera -> body rotation (R_body_cam); identity = the camera frame is the body frame.
  Mat3 R_body_cam = Mat3::Identity();
};

/// The per-frame tracker (sensors/tracking/star_tracker.hpp) with its database: frames in
/// time order, each with optional FrameInputs (a gyro rate, or a filter's prediction).
class Tracker {
 public:
  /// Without `db`, builds one for `camera` (Database::forCamera). Throws InputError for
  /// invalid settings. A frame identical to the previous one (a frozen readout) is not
  /// processed: FrameFailure::kFrozenImage.
  explicit Tracker(const CameraModel& camera, const TrackerSettings& settings = {},
                   std::optional<Database> db = std::nullopt);
  Tracker(const CameraModel& camera, const TrackerOptions& options,
          std::optional<Database> db = std::nullopt);
  ~Tracker();
  Tracker(Tracker&&) noexcept;
  Tracker& operator=(Tracker&&) noexcept;
  FrameResult process(const cv::Mat& image, double t_s, const FrameInputs& in = {});
  void reset();
  StarTracker& tracker();
  const Database& database() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace st::api

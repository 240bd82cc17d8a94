/// @file identifier.hpp
/// Lost-in-space star identification: observations (camera-frame unit vectors with sigmas)
/// + star database + camera -> identified stars and a verified attitude. Every algorithm
/// only proposes hypotheses ("these observations are these catalog stars"); the base class
/// verifies each one with the shared Verifier (verify.hpp), keeps the bookkeeping and the
/// timings, and stops at the first hypothesis whose false-match probability is below the
/// threshold. An implementer overrides doIdentify() and calls ctx.tryHypothesis().
///
/// Algorithms (one registry table, registry.cpp): "pyramid" (default), "voting", "liebe",
/// "planar", "spherical", "nvertex". A new one is its own file defining
/// `std::unique_ptr<StarIdentifier> identify_detail::makeX(const IdentifyOptions&)` plus one
/// line in that table (or one ST_REGISTER_FAMILY_MEMBER line for an algorithm compiled into
/// an executable, common/family_registry.hpp); tests/identify's shared suite runs over every
/// registered name.
///
/// Failures: bad options (an unknown solver name included) are refused once, by create();
/// identify() then only returns outcomes (IdentifyStatus). Star pairs come from StarDatabase::pairsInRange (the
/// k-vector) with a tolerance of `pair_sigma` standard deviations of the inter-star angle.
///
/// Thread safety: an identifier keeps scratch buffers between calls; use one per thread.
#pragma once
#include <chrono>
#include <optional>
#include <memory>
#include <string>
#include <vector>

#include "catalog/star_database.hpp"
#include "sensors/attitude/wahba.hpp"
#include "sensors/camera/camera_model.hpp"
#include "sensors/identify/star_match.hpp"
#include "sensors/identify/star_observation.hpp"
#include "sensors/identify/verify.hpp"

namespace st {

enum class IdentifyStatus {
  Solved,       ///< a hypothesis passed verification
  TooFewStars,  ///< fewer observations than the algorithm needs
  NoMatch,      ///< no pattern of the catalog fits the observations
  Rejected,     ///< patterns fitted, but every hypothesis failed verification
};
const char* toString(IdentifyStatus s);

struct IdentifyOptions {
  double pair_sigma = 4.0;       ///< pair tolerance, in sigma of the inter-star angle
  double scale_tolerance = 0.0;  ///< relative focal-length uncertainty (FOV search): widens
                                 ///< pair tolerances by scale_tolerance * angle
  int max_stars = 12;            ///< brightest observations used to form patterns
  int max_stars_retry = 30;      ///< when those fail, one more search over this many
  int max_verifications = 300;   ///< hypotheses verified before giving up
  long max_candidates = 2000000; ///< pattern candidates examined before giving up
  std::string solver = WahbaSolver::defaultName();  ///< Wahba solver (sensors/attitude/wahba.hpp)
  /// [mag] > 0: a field of 2 or 3 stars (too few for the algorithm) is identified with the
  /// magnitude tie-break (few_stars.hpp); the 1-sigma of one star's magnitude against catalog
  /// V (the photometric scatter `solve` reports, catalog error included). 0: off, such a
  /// field is TooFewStars.
  double magnitude_sigma = 0;
  VerifyOptions verify;          ///< scale_tolerance is copied from above
  /// When set, the search gives up at this time like at a used-up budget (solve --cpulimit:
  /// a limit between tries alone let one try with a huge tolerance run on).
  std::optional<std::chrono::steady_clock::time_point> deadline;

  /// True when all values are usable (the solver name included); otherwise false with `why`
  /// naming the field.
  bool isValid(std::string* why = nullptr) const;
};

struct IdentifyTimings {
  double pattern_ms = 0;  ///< pattern search (k-vector lookups, voting, ...)
  double verify_ms = 0;   ///< verification and attitude refinement
  double total_ms = 0;
};

struct IdentifyResult {
  IdentifyStatus status = IdentifyStatus::NoMatch;
  std::string reason;                  ///< empty when solved
  std::string algorithm;
  /// The camera's attitude, v_i = R(q_ic) v_cam (identification sees camera-frame vectors).
  Quat q_ic = Quat::Identity();
  Mat3 cov_cam = Mat3::Zero();         ///< [rad^2] camera frame (conventions.hpp)
  std::vector<StarMatch> matches;      ///< sorted by observation index
  double false_match_probability = 1;  ///< of the accepted (or best rejected) hypothesis
  double rms_residual = 0;             ///< [rad]
  double rms_residual_px = 0;          ///< [px]
  int hypotheses_tried = 0;            ///< hypotheses verified
  double attitudes_examined = 0;       ///< candidate attitudes the search looked at
  int stars_used = 0;                  ///< observations used to form patterns
  IdentifyTimings timing;
  bool solved() const { return status == IdentifyStatus::Solved; }
};

class SearchContext;

class StarIdentifier {
 public:
  virtual ~StarIdentifier();
  /// Non-virtual entry: sets up the search, runs doIdentify(), fills the result.
  IdentifyResult identify(const std::vector<StarObservation>& obs, const StarDatabase& db,
                          const CameraModel& camera) const;

  virtual std::string name() const = 0;
  const IdentifyOptions& options() const { return options_; }
  /// For temporary tolerance changes (FOV search). The solver is fixed at construction:
  /// changing options().solver afterwards is a bug (asserted in identify()).
  IdentifyOptions& mutableOptions() { return options_; }

  /// nullptr (and *error set) for an unknown name or invalid options (an unknown solver
  /// name included): the only place where identification options are validated.
  static std::unique_ptr<StarIdentifier> create(const std::string& name,
                                                const IdentifyOptions& options = {},
                                                std::string* error = nullptr);
  static std::vector<std::string> names();  ///< from the registry table, default first
  static std::string help();                ///< "name: one line" per algorithm
  static std::string defaultName() { return "pyramid"; }

  using Make = std::unique_ptr<StarIdentifier>(const IdentifyOptions&);  ///< a member's factory
  using Factory = Make*;
  /// Runtime hook behind ST_REGISTER_FAMILY_MEMBER (common/family_registry.hpp).
  static void registerMember(const std::string& name, const std::string& help, Factory make);

 protected:
  /// Precondition: options.isValid() (create() checks it; a factory called with invalid
  /// options is a bug).
  explicit StarIdentifier(const IdentifyOptions& options);
  /// Smallest number of observations the algorithm needs.
  virtual int minStars() const { return 4; }
  /// Observations below which the algorithm cannot run: max(minStars(), verify.min_matches).
  int starsNeeded() const;

 private:
  virtual void doIdentify(SearchContext& ctx) const = 0;
  IdentifyResult finishResult(SearchContext& ctx, IdentifyResult res,
                              std::chrono::steady_clock::time_point t0) const;
  IdentifyOptions options_;
  std::unique_ptr<WahbaSolver> solver_;  ///< options_.solver, made once at construction
  struct Scratch;
  mutable std::unique_ptr<Scratch> scratch_;
};

}  // namespace st

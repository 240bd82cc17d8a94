/// @file star_database.hpp
/// The on-board star database built by the ground program (seed 000 "GP"): the selected stars
/// at the observation epoch, the sorted star-pair array with its k-vector (seed 000 eqs.
/// 11-14), a cone/FOV index (seed 002 spherical-polygon search: k-vectors on x, y, z) and the
/// star-neighbourhood table (seed 002 Table I). Built once by `startracker catalog build`,
/// saved as one versioned binary file and loaded in milliseconds.
#pragma once
#include <limits>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "catalog/cone_index.hpp"
#include "catalog/kvector.hpp"
#include "catalog/star_catalog.hpp"
#include "common/attitude.hpp"
#include "common/huge_page_allocator.hpp"

namespace st {

struct Star {
  uint32_t id;  ///< catalog id (HIP or HR); for a merged double star the brightest member's
  Vec3 u_i;     ///< unit vector, ICRS at the database epoch
  float mag;    ///< V magnitude (combined for a merged double star)
  /// B-V colour of the catalog entry `id` (NaN when unknown, or in a format-3 file): kept so
  /// that photometry's colour term needs no catalog read.
  float bv = std::numeric_limits<float>::quiet_NaN();
};

/// A star the database does not identify but whose light can fall on one it does: fainter
/// than the limit by up to the merge margin, or dropped by the uniform-density reduction.
/// Only its place and brightness are kept: the tracking windows' blend screen.
struct ScreenStar {
  Vec3 u_i;   ///< unit vector, ICRS at the database epoch
  float mag;  ///< V magnitude
};

struct StarPair {
  uint32_t a, b;  ///< indices into stars(), a < b
  float theta;    ///< [rad] separation
};
static_assert(sizeof(StarPair) == 12, "StarPair is stored 12 bytes per pair");

struct PairSlice {
  const StarPair* begin;
  const StarPair* end;
  std::size_t size() const { return std::size_t(end - begin); }
};

struct DatabaseParams {
  double max_pair_angle;         ///< [rad] pairs up to this separation (camera diagonal FOV + margin)
  double mag_limit;              ///< keep V <= mag_limit (after build: the effective limit,
                                 ///< min(requested, the catalog's depth))
  double epoch_jyear;            ///< observation epoch for proper motion / aberration
  bool aberration = true;        ///< annual aberration on
  double double_star_sep;        ///< [rad] merge closer stars (seed 004 eq. 6.1/6.2); 0 = off
  int max_stars_per_region = 0;  ///< 0 = no uniform-density reduction
  double neighbour_radius;       ///< [rad] for the neighbour table (seed 002)
  // --- additions ---
  bool parallax = true;      ///< annual parallax (observer at the Earth, not the barycentre)
  double region_radius = 0;  ///< [rad] cone of the density reduction; 0 = max_pair_angle / 2

  /// True when all values are usable; otherwise false with `why` naming the field.
  bool isValid(std::string* why = nullptr) const;
};

/// Counts at each step of DatabaseParams-driven selection (what `catalog info` prints).
struct BuildReport {
  std::string catalog_name;
  double catalog_epoch_jyear = 0;
  std::string catalog_path;               ///< the file the catalog was read from
  /// [mag] the catalog's depth (StarCatalog::depth_vmag); NaN in a format-1 database file.
  double catalog_depth_vmag = 0;
  /// [mag] the limit asked for; params().mag_limit is min(this, catalog_depth_vmag).
  double requested_mag_limit = 0;
  std::size_t catalog_entries = 0;        ///< entries with a position in the catalog
  std::size_t skipped_no_position = 0;    ///< catalog entries without a position
  std::size_t merge_candidates = 0;       ///< V <= mag_limit + merge margin, entering the merge
  std::size_t double_star_groups = 0;     ///< groups of >= 2 stars merged into one
  std::size_t stars_merged_away = 0;      ///< stars absorbed into a brighter member
  std::size_t after_mag_limit = 0;        ///< after the merge, V <= mag_limit
  std::size_t after_density = 0;          ///< after the uniform-density reduction
  std::size_t screen_stars = 0;           ///< candidates not kept: the blend screen
  std::size_t pairs = 0;
  std::size_t kvector_size = 0;
  std::size_t neighbour_entries = 0;
  double build_seconds = 0;
};

/// The pairs, sorted by angle: the database's largest array (huge_page_allocator.hpp).
using PairList = std::vector<StarPair, HugePageAllocator<StarPair>>;

/// A build stopped by its StopFn (solve --cpulimit): nothing is kept.
class BuildStopped : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class StarDatabase {
 public:
  /// A limit beyond the catalog's depth is capped to it (warned once, effectiveMagLimit()); a
  /// limit that keeps no star is an InputError naming the limit and the catalog.
  static StarDatabase build(const StarCatalog&, const DatabaseParams&);
  /// The same, calling `progress` with a one-line message before each step (for the CLI).
  using ProgressFn = std::function<void(const std::string&)>;
  /// True when the build is to stop (a time limit): checked between steps and every few
  /// hundred stars inside the pair and neighbour loops; the build then throws BuildStopped.
  using StopFn = std::function<bool()>;
  static StarDatabase build(const StarCatalog&, const DatabaseParams&, const ProgressFn& progress,
                            const StopFn& stop = StopFn());
  static std::string defaultCatalogPath();  ///< hip_main_v6.6.dat.gz in $STARTRACKER_DATA_DIR, else <program>/../share/startracker, else catalog/data
  /// The file format save() writes by default (format 4: B-V per star).
  static constexpr uint32_t kFileFormat = 4;
  /// Writes the versioned binary file; throws InputError if it cannot be written. An older
  /// `format` (2: no blend screen, no B-V; 3: no B-V) is for readers of those versions.
  void save(const std::string& path, uint32_t format = kFileFormat) const;
  /// InputError (naming the file) on bad magic/version/checksum or a truncated file. Reads
  /// format 3 and the older 2 (no blend-screen stars) and 1 (nor catalog path, depth or
  /// requested limit).
  static StarDatabase load(const std::string& path);

  const std::vector<Star>& stars() const { return stars_; }  ///< sorted brightest first
  const DatabaseParams& params() const { return params_; }
  const BuildReport& report() const { return report_; }
  /// All pairs sorted by theta (ascending).
  const PairList& pairs() const { return pairs_; }
  const KVector& pairKVector() const { return pair_kv_; }

  /// Pairs with theta in [theta_lo, theta_hi]: k-vector, O(1 + matches), exact w.r.t. the
  /// stored float theta.
  PairSlice pairsInRange(double theta_lo, double theta_hi) const;

  /// Indices of the stars within `radius` of `axis_i` (unit vector), ascending (= brightest
  /// first). `out` is cleared first.
  void coneQuery(const Vec3& axis_i, double radius, std::vector<uint32_t>& out) const;

  /// Indices of the stars whose gnomonic projection lies in the rectangle
  /// |x/z| <= tan_half_x, |y/z| <= tan_half_y of the camera at attitude q_ib (camera +z the
  /// boresight, conventions.hpp), ascending. A pinhole approximation of the image rectangle:
  /// pad the half-angles for distortion.
  void rectangleQuery(const Quat& q_ib, double tan_half_x, double tan_half_y,
                      std::vector<uint32_t>& out) const;

  /// Stars kept only for the blend screen (ScreenStar), brightest first; empty in a database
  /// file of format < 3.
  const std::vector<ScreenStar>& screenStars() const { return screen_; }
  /// Indices into screenStars() within `radius` of `axis_i`, ascending. `out` is cleared.
  void screenConeQuery(const Vec3& axis_i, double radius, std::vector<uint32_t>& out) const {
    screen_cone_.query(axis_i, radius, out);
  }

  /// Neighbours of star i within params().neighbour_radius, nearest first (seed 002 Table I).
  const uint32_t* neighboursBegin(uint32_t i) const { return nbr_.data() + nbr_start_[i]; }
  const uint32_t* neighboursEnd(uint32_t i) const { return nbr_.data() + nbr_start_[i + 1]; }

 private:
  void buildIndexes();  ///< the cone indexes of stars_ and screen_ (also after load)
  void buildPairs(const StopFn& stop);
  void buildNeighbours(const StopFn& stop);

  DatabaseParams params_{};
  BuildReport report_;
  std::vector<Star> stars_;
  PairList pairs_;
  KVector pair_kv_;
  ConeIndex cone_;         ///< over stars_ (seed 002)
  std::vector<ScreenStar> screen_;
  ConeIndex screen_cone_;  ///< over screen_
  std::vector<uint32_t> nbr_start_{0};
  std::vector<uint32_t, HugePageAllocator<uint32_t>> nbr_;
};

}  // namespace st

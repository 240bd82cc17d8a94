// StarDatabase: building the search structures and querying them.
#include "catalog/star_database.hpp"

#include <unordered_map>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <numeric>

#include "catalog/epoch_correction.hpp"
#include "catalog/star_selection.hpp"
#include "common/conventions.hpp"
#include "common/errors.hpp"

namespace st {
namespace {

// Stars up to this much fainter than the limit enter the double-star merge and, if not
// merged, the blend screen: a companion 2.5 mag fainter still brightens the blend by 0.10 mag
// and pulls its centroid by a tenth of their separation.
constexpr double kMergeMagMargin = 2.5;

// Fibonacci lattice of n nearly uniform directions (centres of the density-reduction cones).
std::vector<Vec3> fibonacciSphere(std::size_t n) {
  std::vector<Vec3> v(n);
  const double golden = kPi * (3.0 - std::sqrt(5.0));
  for (std::size_t k = 0; k < n; ++k) {
    const double z = 1.0 - (2.0 * k + 1.0) / double(n);
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    v[k] = Vec3(r * std::cos(golden * k), r * std::sin(golden * k), z);
  }
  return v;
}

}  // namespace

bool DatabaseParams::isValid(std::string* why) const {
  std::string e;
  auto bad = [&](const std::string& what) {
    if (e.empty()) e = "DatabaseParams." + what;
  };
  if (!(max_pair_angle > 0 && max_pair_angle < kPi))
    bad("max_pair_angle must be in (0, 180) deg, got " + std::to_string(rad2deg(max_pair_angle)));
  if (!std::isfinite(mag_limit)) bad("mag_limit must be finite");
  if (!std::isfinite(epoch_jyear) || epoch_jyear < 1000 || epoch_jyear > 3000)
    bad("epoch_jyear must be a Julian year in [1000, 3000], got " + std::to_string(epoch_jyear));
  if (!(double_star_sep >= 0 && double_star_sep < deg2rad(1)))
    bad("double_star_sep must be in [0, 1) deg");
  if (max_stars_per_region < 0) bad("max_stars_per_region must be >= 0");
  if (!(neighbour_radius >= 0 && neighbour_radius < kPi))
    bad("neighbour_radius must be in [0, 180) deg");
  if (!(region_radius >= 0 && region_radius < kPi)) bad("region_radius must be in [0, 180) deg");
  if (why) *why = e;
  return e.empty();
}

std::string StarDatabase::defaultCatalogPath() {
  // An installed tree or an extracted .deb is found from the program's own place, so it
  // works wherever it was unpacked; $STARTRACKER_DATA_DIR overrides (a Python interpreter's
  // place says nothing about the module's).
  namespace fs = std::filesystem;
  static const std::string kFile = "hip_main_v6.6.dat.gz";
  if (const char* env = std::getenv("STARTRACKER_DATA_DIR"); env && *env)
    return (fs::path(env) / kFile).string();
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) {
    const fs::path installed = exe.parent_path().parent_path() / "share" / "startracker" / kFile;
    if (fs::exists(installed, ec)) return installed.string();
  }
  const fs::path source = fs::path(ST_CATALOG_DATA_DIR) / kFile;
  if (fs::exists(source, ec)) return source.string();
  return (fs::path(ST_CATALOG_INSTALL_DIR) / kFile).string();
}

StarDatabase StarDatabase::build(const StarCatalog& cat, const DatabaseParams& params) {
  return build(cat, params, ProgressFn());
}

namespace {

std::string fmtMag(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.2f", v);
  return b;
}

void say(const StarDatabase::ProgressFn& progress, const std::string& m) {
  if (progress) progress(m);
}

// 1. Candidates, corrected to the observation epoch (proper motion, parallax, aberration).
std::vector<SelectedStar> epochCorrectedCandidates(const StarCatalog& cat,
                                                   const DatabaseParams& params,
                                                   const StarDatabase::ProgressFn& progress) {
  const double merge_limit = params.mag_limit + kMergeMagMargin;
  say(progress, "correcting " + std::to_string(cat.entries.size()) +
                    " catalog positions to epoch " + std::to_string(params.epoch_jyear));
  const EarthState earth = earthBarycentricState(params.epoch_jyear);
  std::vector<SelectedStar> sel;
  for (const CatalogEntry& e : cat.entries) {
    if (!(e.vmag <= merge_limit)) continue;
    Vec3 u = propagateSpaceMotion(e, cat.epoch_jyear, params.epoch_jyear);
    if (params.parallax) u = applyParallax(u, e.parallax, earth.position_au);
    if (params.aberration) u = applyAberration(u, earth.velocity_km_s);
    sel.push_back({e.id, u, e.vmag});
  }
  return sel;
}

// 2. Double stars (seed 004 eqs. 6.1/6.2), then 3. the magnitude limit on the blends; the
// survivors brightest first. The fainter ones go to `screen`.
void mergeAndLimit(std::vector<SelectedStar>& sel, const DatabaseParams& params,
                   BuildReport& rep, std::vector<ScreenStar>& screen,
                   const StarDatabase::ProgressFn& progress) {
  say(progress, "merging double stars among " + std::to_string(sel.size()) + " candidates");
  sel = mergeDoubleStars(sel, params.double_star_sep, &rep.double_star_groups,
                         &rep.stars_merged_away);
  std::sort(sel.begin(), sel.end(), [](const SelectedStar& a, const SelectedStar& b) {
    return a.mag != b.mag ? a.mag < b.mag : a.id < b.id;
  });
  const auto faint = std::partition_point(
      sel.begin(), sel.end(), [&](const SelectedStar& s) { return s.mag <= params.mag_limit; });
  for (auto it = faint; it != sel.end(); ++it) screen.push_back({it->u, float(it->mag)});
  sel.erase(faint, sel.end());
  rep.after_mag_limit = sel.size();
}

// 4. Uniform density (seed 004 sec. 5.5.4): sweep cone centres over the sky and keep the
// N brightest stars of every cone; a star survives if some cone keeps it.
// The stars it drops go to `screen`.
std::vector<Star> uniformDensityStars(const StarDatabase& db, const DatabaseParams& params,
                                      std::vector<ScreenStar>& screen,
                                      const StarDatabase::ProgressFn& progress) {
  const double radius =
      params.region_radius > 0 ? params.region_radius : params.max_pair_angle / 2;
  const double step = std::min(deg2rad(1.0), radius / 4);  // the seed sweeps 1 deg steps
  const std::size_t n_centres = std::size_t(std::ceil(4 * kPi / (step * step)));
  say(progress, "uniform density: keeping the " + std::to_string(params.max_stars_per_region) +
                    " brightest stars in each of " + std::to_string(n_centres) + " cones");
  const std::vector<Star>& stars = db.stars();
  std::vector<char> keep(stars.size(), 0);
  std::vector<uint32_t> in_cone;
  for (const Vec3& c : fibonacciSphere(n_centres)) {
    db.coneQuery(c, radius, in_cone);  // ascending index = brightest first
    const std::size_t k = std::min<std::size_t>(in_cone.size(), params.max_stars_per_region);
    for (std::size_t j = 0; j < k; ++j) keep[in_cone[j]] = 1;
  }
  std::vector<Star> kept;
  for (std::size_t i = 0; i < stars.size(); ++i)
    if (keep[i]) kept.push_back(stars[i]);
    else screen.push_back({stars[i].u_i, stars[i].mag});
  return kept;
}

}  // namespace

namespace {
/// Every this many stars the pair and neighbour loops ask whether to stop (~1 ms of work at
/// the widest field's few thousand pairs per star).
constexpr uint32_t kStopCheckStars = 64;

void stopIfAsked(const StarDatabase::StopFn& stop) {
  if (stop && stop()) throw BuildStopped("the star database build was stopped");
}
}  // namespace

StarDatabase StarDatabase::build(const StarCatalog& cat, const DatabaseParams& params_in,
                                 const ProgressFn& progress, const StopFn& stop) {
  requireValid(params_in);  // the ground program's edge: InputError naming the field
  const auto t0 = std::chrono::steady_clock::now();
  StarDatabase db;
  DatabaseParams params = params_in;
  params.mag_limit = effectiveMagLimit(cat, params_in.mag_limit);
  db.params_ = params;
  BuildReport& rep = db.report_;
  rep.catalog_name = cat.name;
  rep.catalog_epoch_jyear = cat.epoch_jyear;
  rep.catalog_path = cat.source_path;
  rep.catalog_depth_vmag = cat.depth_vmag;
  rep.requested_mag_limit = params_in.mag_limit;
  rep.catalog_entries = cat.entries.size();
  rep.skipped_no_position = cat.skipped_no_position;

  std::vector<SelectedStar> sel = epochCorrectedCandidates(cat, params, progress);
  rep.merge_candidates = sel.size();
  mergeAndLimit(sel, params, rep, db.screen_, progress);
  if (sel.empty()) {
    double brightest = cat.entries.empty() ? 0 : cat.entries[0].vmag;
    for (const CatalogEntry& e : cat.entries) brightest = std::min(brightest, e.vmag);
    throw InputError("magnitude limit V " + fmtMag(params.mag_limit) + " keeps no star of " +
                     cat.source_path + " (its brightest is V " + fmtMag(brightest) + ")");
  }
  db.stars_.reserve(sel.size());
  std::unordered_map<uint32_t, double> bv_of;  // a merged group's colour: its id's entry
  for (const CatalogEntry& e : cat.entries) bv_of.emplace(e.id, e.bv);
  for (const SelectedStar& s : sel) {
    const auto it = bv_of.find(s.id);
    db.stars_.push_back({s.id, s.u, float(s.mag),
                         it == bv_of.end() ? std::numeric_limits<float>::quiet_NaN() : float(it->second)});
  }
  if (params.max_stars_per_region > 0) {
    db.buildIndexes();  // the density reduction's cone queries
    std::vector<Star> kept = uniformDensityStars(db, params, db.screen_, progress);
    db.stars_.swap(kept);
  }
  rep.after_density = db.stars_.size();
  std::stable_sort(db.screen_.begin(), db.screen_.end(),
                   [](const ScreenStar& a, const ScreenStar& b) { return a.mag < b.mag; });
  rep.screen_stars = db.screen_.size();
  db.buildIndexes();
  stopIfAsked(stop);

  // 5. Pairs + k-vector, 6. neighbour table.
  say(progress, "building star pairs and k-vector for " + std::to_string(db.stars_.size()) +
                    " stars");
  db.buildPairs(stop);
  say(progress, "building the neighbour table (" + std::to_string(db.pairs_.size()) + " pairs)");
  db.buildNeighbours(stop);
  rep.pairs = db.pairs_.size();
  rep.kvector_size = db.pair_kv_.size();
  rep.neighbour_entries = db.nbr_.size();
  rep.build_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return db;
}

void StarDatabase::buildIndexes() {
  std::vector<Vec3> u(stars_.size());
  for (std::size_t k = 0; k < u.size(); ++k) u[k] = stars_[k].u_i;
  cone_.build(u);
  u.resize(screen_.size());
  for (std::size_t k = 0; k < u.size(); ++k) u[k] = screen_[k].u_i;
  screen_cone_.build(u);
}

void StarDatabase::buildPairs(const StopFn& stop) {
  pairs_.clear();
  std::vector<uint32_t> near;
  for (uint32_t i = 0; i < stars_.size(); ++i) {
    if (i % kStopCheckStars == 0) stopIfAsked(stop);
    coneQuery(stars_[i].u_i, params_.max_pair_angle, near);
    for (uint32_t j : near) {
      if (j <= i) continue;
      const Vec3& a = stars_[i].u_i;
      const Vec3& b = stars_[j].u_i;
      // atan2 keeps full precision for close pairs, where acos(dot) loses digits.
      pairs_.push_back({i, j, float(std::atan2(a.cross(b).norm(), a.dot(b)))});
    }
  }
  stopIfAsked(stop);
  std::sort(pairs_.begin(), pairs_.end(), [](const StarPair& p, const StarPair& q) {
    if (p.theta != q.theta) return p.theta < q.theta;
    return p.a != q.a ? p.a < q.a : p.b < q.b;
  });
  stopIfAsked(stop);
  pair_kv_.build(pairs_.size(), [&](std::size_t k) { return double(pairs_[k].theta); });
}

void StarDatabase::buildNeighbours(const StopFn& stop) {
  nbr_start_.assign(1, 0);
  nbr_.clear();
  std::vector<uint32_t> near;
  std::vector<std::pair<double, uint32_t>> by_dist;
  for (uint32_t i = 0; i < stars_.size(); ++i) {
    if (i % kStopCheckStars == 0) stopIfAsked(stop);
    if (params_.neighbour_radius > 0) coneQuery(stars_[i].u_i, params_.neighbour_radius, near);
    else near.clear();
    by_dist.clear();
    for (uint32_t j : near)
      if (j != i) by_dist.push_back({-stars_[i].u_i.dot(stars_[j].u_i), j});
    std::sort(by_dist.begin(), by_dist.end());  // nearest first
    for (const auto& d : by_dist) nbr_.push_back(d.second);
    nbr_start_.push_back(uint32_t(nbr_.size()));
  }
}

PairSlice StarDatabase::pairsInRange(double theta_lo, double theta_hi) const {
  const auto r = pair_kv_.range(theta_lo, theta_hi,
                                [&](std::size_t k) { return double(pairs_[k].theta); });
  const StarPair* base = pairs_.data();
  return {base + r.first, base + r.second};
}

void StarDatabase::coneQuery(const Vec3& axis_i, double radius, std::vector<uint32_t>& out) const {
  cone_.query(axis_i, radius, out);
}

void StarDatabase::rectangleQuery(const Quat& q_ib, double tan_half_x, double tan_half_y,
                                  std::vector<uint32_t>& out) const {
  const Mat3 R_ib = q_ib.normalized().toRotationMatrix();
  const Vec3 boresight_i = R_ib.col(2);
  coneQuery(boresight_i, std::atan(std::hypot(tan_half_x, tan_half_y)), out);
  std::size_t kept = 0;
  for (uint32_t idx : out) {
    const Vec3 v_c = R_ib.transpose() * stars_[idx].u_i;
    if (v_c.z() > 0 && std::fabs(v_c.x()) <= tan_half_x * v_c.z() &&
        std::fabs(v_c.y()) <= tan_half_y * v_c.z())
      out[kept++] = idx;
  }
  out.resize(kept);
}

}  // namespace st

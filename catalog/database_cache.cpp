#include "catalog/database_cache.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cinttypes>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <utility>
#include <vector>

#include "catalog/star_catalog.hpp"
#include "common/errors.hpp"
#include "common/log.hpp"

namespace st {
namespace fs = std::filesystem;

namespace {

/// Bumped when the database file format or the build changes in a way the parameters do not
/// show, so that old cache files are never mistaken for current ones.
constexpr int kCacheGeneration = 3;  // 3: B-V per star (database format 4)

std::uint64_t fnv1a(const std::string& s) {
  std::uint64_t h = 1469598103934665603ull;
  for (unsigned char c : s) h = (h ^ c) * 1099511628211ull;
  return h;
}

/// The catalog file's identity: a different file at the same path (an update) is a new key.
std::string catalogIdentity(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return path + "|missing";
  char b[128];
  std::snprintf(b, sizeof b, "|%lld|%lld.%09ld", static_cast<long long>(st.st_size),
                static_cast<long long>(st.st_mtim.tv_sec), st.st_mtim.tv_nsec);
  return fs::absolute(path).string() + b;
}

/// Keeps the folder bounded: the files beyond the kKeep most recently used (a hit touches its
/// file) are removed. A file another process is reading stays readable until it closes it.
constexpr std::size_t kKeep = 16;  // ~8 MB each for a 10-20 deg camera

void evictOld(const std::string& dir) {
  std::vector<std::pair<fs::file_time_type, fs::path>> files;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec)) {
    const std::string name = e.path().filename().string();
    if (name.rfind("db-", 0) == 0 && e.path().extension() == ".stdb")
      files.emplace_back(e.last_write_time(ec), e.path());
  }
  if (files.size() <= kKeep) return;
  std::sort(files.begin(), files.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  for (std::size_t i = kKeep; i < files.size(); ++i) fs::remove(files[i].second, ec);
}

bool sameParams(const DatabaseParams& a, const DatabaseParams& b) {
  return a.max_pair_angle == b.max_pair_angle && a.epoch_jyear == b.epoch_jyear &&
         a.aberration == b.aberration && a.double_star_sep == b.double_star_sep &&
         a.max_stars_per_region == b.max_stars_per_region &&
         a.neighbour_radius == b.neighbour_radius && a.parallax == b.parallax &&
         a.region_radius == b.region_radius;
}

}  // namespace

std::string databaseCacheDir() {
  const char* xdg = std::getenv("XDG_CACHE_HOME");
  if (xdg != nullptr && *xdg == '/') return std::string(xdg) + "/startracker";
  const char* home = std::getenv("HOME");
  if (home != nullptr && *home != '\0') return std::string(home) + "/.cache/startracker";
  return "";
}

std::string databaseCacheName(const DatabaseParams& p, const std::string& catalog_path) {
  char b[512];
  std::snprintf(b, sizeof b, "gen%d|%a|%a|%a|%d|%a|%d|%a|%d|%a|", kCacheGeneration,
                p.max_pair_angle, p.mag_limit, p.epoch_jyear, int(p.aberration),
                p.double_star_sep, p.max_stars_per_region, p.neighbour_radius, int(p.parallax),
                p.region_radius);
  char name[64];
  std::snprintf(name, sizeof name, "db-%016" PRIx64 ".stdb",
                fnv1a(b + catalogIdentity(catalog_path)));
  return name;
}

DatabaseCache::DatabaseCache(std::string catalog_path, bool use_disk)
    : catalog_path_(std::move(catalog_path)), use_disk_(use_disk) {}

CachedDatabase DatabaseCache::get(const DatabaseParams& p, const StarDatabase::StopFn& stop) {
  // One build at a time: the threads of a batch want the same database, built once.
  std::lock_guard<std::mutex> lock(mutex_);
  const std::string key = databaseCacheName(p, catalog_path_);
  auto it = memory_.find(key);
  if (it != memory_.end()) return it->second;
  CachedDatabase built = loadOrBuild(p, stop);  // a stopped build throws: nothing kept
  return memory_[key] = std::move(built);
}

CachedDatabase DatabaseCache::loadOrBuild(const DatabaseParams& p,
                                          const StarDatabase::StopFn& stop) {
  CachedDatabase out;
  const std::string dir = use_disk_ ? databaseCacheDir() : "";
  const std::string path = dir.empty() ? "" : dir + "/" + databaseCacheName(p, catalog_path_);
  if (!path.empty() && fs::exists(path)) {
    try {
      auto db = std::make_shared<StarDatabase>(StarDatabase::load(path));
      if (sameParams(db->params(), p)) {
        out.db = std::move(db);
        out.how = "read from the cache " + path + ", built";
        std::error_code ec;
        fs::last_write_time(path, fs::file_time_type::clock::now(), ec);  // recently used
        return out;
      }
      log::warn("star database cache %s holds other parameters: rebuilding it", path.c_str());
    } catch (const std::exception& e) {
      log::warn("star database cache %s is unreadable (%s): rebuilding it", path.c_str(), e.what());
    }
  }
  out.db = std::make_shared<StarDatabase>(
      StarDatabase::build(loadCatalog(catalog_path_), p, StarDatabase::ProgressFn(), stop));
  out.how = "built in memory";
  if (path.empty()) return out;
  // pid + counter: unique among every process and thread writing into the folder.
  static std::atomic<int> counter{0};
  const std::string tmp =
      path + ".tmp." + std::to_string(::getpid()) + "." + std::to_string(counter++);
  try {
    std::error_code ec;
    fs::create_directories(dir, ec);
    out.db->save(tmp);
    fs::rename(tmp, path);
    out.how = "cached in " + path + ", built";
    evictOld(dir);
  } catch (const std::exception& e) {
    std::error_code ec;
    fs::remove(tmp, ec);
    log::warn("star database cache %s not written (%s); --no-cache skips the cache", path.c_str(),
              e.what());
  }
  return out;
}

std::shared_ptr<const StarDatabase> cameraDatabase(const CameraDatabaseRecipe& r,
                                                   const std::string& catalog_path, bool use_disk,
                                                   std::string* how,
                                                   const StarDatabase::StopFn& stop) {
  // One cache per catalog file and disk policy, for the life of the process.
  static std::mutex mutex;
  static std::map<std::pair<std::string, bool>, std::unique_ptr<DatabaseCache>> caches;
  const std::string cat = catalog_path.empty() ? StarDatabase::defaultCatalogPath() : catalog_path;
  DatabaseCache* cache = nullptr;
  {
    std::lock_guard<std::mutex> lock(mutex);
    auto& slot = caches[{cat, use_disk}];
    if (!slot) slot = std::make_unique<DatabaseCache>(cat, use_disk);
    cache = slot.get();
  }
  CachedDatabase c = cache->get(databaseParams(r), stop);
  if (how) *how = c.how;
  return c.db;
}

}  // namespace st

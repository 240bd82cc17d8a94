/// @file database_cache.hpp
/// The star databases `solve` builds when no --database is given, built once and kept:
///  - in the process, keyed by their parameters (a batch of same-size frames builds one);
///  - on disk in $XDG_CACHE_HOME/startracker (else ~/.cache/startracker), one file per key,
///    the key a hash of the parameters, the catalog file's identity (path, size, mtime) and
///    the database format. A file is written to a temporary name in the same folder and
///    renamed over, so concurrent writers never expose a partial file (the last rename
///    wins; every writer wrote the same bytes). A file that fails to load (the format's
///    checksum, a truncation) or holds other parameters is rebuilt with a warning.
/// The folder keeps the 16 most recently used files (~8 MB each); older ones are removed
/// when a new one is written.
/// No usable cache folder (no HOME, read-only) costs a warning and an in-memory build.
#pragma once
#include <map>
#include <memory>
#include <mutex>
#include <string>

#include "catalog/database_recipe.hpp"
#include "catalog/star_database.hpp"

namespace st {

/// The cache folder ("" when neither XDG_CACHE_HOME nor HOME is set).
std::string databaseCacheDir();

/// File name of the database for `p` built from `catalog_path` ("db-<16 hex>.stdb").
std::string databaseCacheName(const DatabaseParams& p, const std::string& catalog_path);

struct CachedDatabase {
  std::shared_ptr<const StarDatabase> db;
  std::string how;  ///< "built in memory", "read from the cache <file>, built", "cached in <file>, built"
};

/// Thread-safe source of in-memory-recipe databases for one run.
class DatabaseCache {
 public:
  /// `use_disk` false (--no-cache): build in memory only.
  DatabaseCache(std::string catalog_path, bool use_disk);
  /// `stop` (optional) ends a build under way (BuildStopped; nothing is kept or cached).
  CachedDatabase get(const DatabaseParams& p, const StarDatabase::StopFn& stop = {});

 private:
  CachedDatabase loadOrBuild(const DatabaseParams& p, const StarDatabase::StopFn& stop);
  std::string catalog_path_;
  bool use_disk_;
  std::mutex mutex_;
  std::map<std::string, CachedDatabase> memory_;
};

/// The one way to the star database of a camera recipe (database_recipe.hpp), for every
/// command and the library: built from `catalog_path` ("" = the default catalog) once per
/// process and kept in the user's cache folder (`use_disk` false: in memory only). `how`
/// (optional) receives where it came from ("built in memory", "read from the cache ...");
/// `stop` (optional: solve's --cpulimit) ends a build under way with BuildStopped.
std::shared_ptr<const StarDatabase> cameraDatabase(const CameraDatabaseRecipe& r,
                                                   const std::string& catalog_path = "",
                                                   bool use_disk = true, std::string* how = nullptr,
                                                   const StarDatabase::StopFn& stop = {});

}  // namespace st

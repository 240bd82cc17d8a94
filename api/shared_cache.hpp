/// @file shared_cache.hpp
/// The facade's databases built in memory, one cache per process (solve/database_cache.hpp):
/// a program that solves frame after frame of one camera builds, or reads from the disk
/// cache, its database once.
#pragma once
#include <memory>

#include "solve/database_cache.hpp"

namespace st::api {

/// The process's cache; `no_cache` true gives the one that never touches the disk.
std::shared_ptr<solve::DatabaseCache> sharedDatabaseCache(bool no_cache = false);

}  // namespace st::api

/// @file run_file.hpp
/// The run file `<experiment>_run[.shard-i-of-N].txt` of `startracker montecarlo`: the
/// options that change results (McOptions' stored part), the shard and the row count, in
/// one [montecarlo_run] section read strictly through its schema (an unknown or misspelled
/// key is an error naming the file and key). `montecarlo merge` rebuilds reports from it.
/// Files written before the section existed (bare key = value lines) still read.
#pragma once
#include <cstdint>
#include <map>
#include <string>

#include "app/montecarlo/mc_options.hpp"
#include "config/ini_kind.hpp"
#include "config/schema.hpp"

namespace st::app::mc {

constexpr const char* kRunSection = kMontecarloRunSection;

struct McRunFile {
  McOptions options;
  std::string shard = "0/1";  ///< i/N
  uint64_t rows = 0;          ///< rows of the trials CSV written with it
};

const SectionSchema<McRunFile>& runFileSchema();
void writeRunFile(const McOptions& o, std::size_t rows, const std::string& path);
McRunFile readRunFile(const std::string& path);
/// The stored options, shard and rows as key -> value (what shards of one run share).
std::map<std::string, std::string> runFileKeyValues(const McRunFile& run);
/// Strict read of section [montecarlo_run]; its effective configuration in ini form.
std::string printRunFile(const IniReader& r, const std::string& section);

}  // namespace st::app::mc

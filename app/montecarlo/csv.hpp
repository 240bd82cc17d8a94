/// @file csv.hpp
/// The CSV and Markdown forms of a table (RFC 4180 quoting when a cell needs it).
#pragma once
#include <string>

#include "app/montecarlo/experiment.hpp"

namespace st::app::mc {

void writeCsv(const Table& t, const std::string& path);  ///< InputError if not writable
Table readCsv(const std::string& path);                  ///< InputError naming file and line
std::string toMarkdown(const Table& t);

}  // namespace st::app::mc

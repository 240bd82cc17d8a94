/// @file utc_time.hpp
/// UTC times as the configuration files write them. One parser for every key that takes a
/// date (a scenario's start_time, a camera folder's frame_start_time).
#pragma once
#include <string>

namespace st {

/// Parses "YYYY-MM-DDTHH:MM:SS[.fff]" (UTC; 'T' or ' ') into Unix seconds; InputError naming
/// `where` if bad.
double parseUtc(const std::string& text, const std::string& where);

}  // namespace st

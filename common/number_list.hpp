/// @file number_list.hpp
/// Parsing of number lists as they appear in .ini values: "[640 480]", "1, 2, 3", "0.1;0.2".
#pragma once
#include <string>
#include <vector>

namespace st {

/// The numbers in `text` (brackets, commas and semicolons count as spaces). Throws
/// InputError "<where>: '<token>' is not a number" on anything else.
std::vector<double> parseNumberList(const std::string& text, const std::string& where);

}  // namespace st

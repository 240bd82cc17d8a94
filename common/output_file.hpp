/// @file output_file.hpp
/// Every output path a command writes is checked before the work starts, so a typo in
/// `--csv` or `--annotate` fails in a second with a clear message instead of losing a
/// finished run. One policy for every command: missing parent folders are created; a path
/// that cannot be written is an InputError naming the flag and the path.
#pragma once
#include <string>

namespace st {

/// Creates the parent folders of `path` and proves the file can be written (an existing file
/// is left untouched; a new one is created empty and removed again). `flag` names the
/// option in the message, e.g. "--csv". Throws InputError.
void prepareOutputFile(const std::string& path, const std::string& flag);

/// Creates folder `dir` (and its parents) and proves a file can be written in it. Throws
/// InputError naming `flag` and `dir`.
void prepareOutputDir(const std::string& dir, const std::string& flag);

}  // namespace st

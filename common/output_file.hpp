/// @file output_file.hpp
/// Every output path a command writes is checked before the work starts, so a typo in
/// `--csv` or `--annotate` fails in a second with a clear message instead of losing a
/// finished run. One policy for every command: missing parent folders are created; a path
/// that cannot be written is an InputError naming the flag and the path.
#pragma once
#include <string>
#include <vector>

namespace st {

/// Creates the parent folders of `path` and proves the file can be written (an existing file
/// is left untouched; a new one is created empty and removed again). `flag` names the
/// option in the message, e.g. "--csv". Throws InputError.
void prepareOutputFile(const std::string& path, const std::string& flag);

/// A path a command reads or writes, and what names it in a message ("the input rawlog",
/// "--csv").
struct NamedPath {
  std::string path, name;
};
/// InputError when the output `path` (named `flag`) is the same file as one of `others`
/// (inputs, or the other outputs): an output never overwrites what the command reads or
/// another output (`replay X.rawlog --csv X.rawlog` used to truncate the recording). Same
/// file: the same path once normalised, or one inode for files that exist. Empty paths are
/// skipped.
void refuseSameFile(const std::string& path, const std::string& flag,
                    const std::vector<NamedPath>& others);

/// Creates folder `dir` (and its parents) and proves a file can be written in it. Throws
/// InputError naming `flag` and `dir`.
void prepareOutputDir(const std::string& dir, const std::string& flag);

}  // namespace st

/// @file output_file.hpp
/// Every output path a command writes is checked before the work starts, so a typo in
/// `--csv` or `--annotate` fails in a second with a clear message instead of losing a
/// finished run. One policy for every command: missing parent folders are created; a path
/// that cannot be written is an InputError naming the flag and the path; an existing file is
/// refused unless the command was given -f/--force (an earlier run's result is not lost to a
/// repeated command line); and the file is written under a temporary name and renamed when
/// complete (PendingOutput), so an interrupted run leaves the earlier file as it was.
#pragma once
#include <cstddef>
#include <string>
#include <vector>

namespace st {

/// Creates the parent folders of `path` and proves the file can be written (an existing file
/// is left untouched; a new one is created empty and removed again). `flag` names the
/// option in the message, e.g. "--csv". An existing file is an InputError unless `replace`
/// (the command's -f/--force). Throws InputError.
void prepareOutputFile(const std::string& path, const std::string& flag, bool replace);


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

/// An output written under a temporary name beside it and renamed to its real name only when
/// complete (commit()), so an interrupted or failed run never leaves a half file under the
/// real name (nor destroys the file an earlier run left there). The temporary is removed
/// when the object dies uncommitted.
class PendingOutput {
 public:
  explicit PendingOutput(std::string path);
  ~PendingOutput();
  PendingOutput(const PendingOutput&) = delete;
  PendingOutput& operator=(const PendingOutput&) = delete;
  /// Where to write: `<folder>/.partial-<name>` (hidden, the extension kept).
  const std::string& tempPath() const { return temp_; }
  const std::string& path() const { return path_; }
  /// Renames the temporary over the real path. Throws InputError naming it on failure.
  void commit();

 private:
  std::string path_, temp_;
  bool committed_ = false;
};

/// Writes `size` bytes to `path` through a PendingOutput (complete or not at all). Throws
/// InputError naming `path`.
void writeFileAtomically(const std::string& path, const char* data, std::size_t size);
inline void writeFileAtomically(const std::string& path, const std::string& text) {
  writeFileAtomically(path, text.data(), text.size());
}

}  // namespace st

#include "common/output_file.hpp"

#include <cstdio>
#include <filesystem>
#include <system_error>

#include "common/errors.hpp"

namespace st {
namespace fs = std::filesystem;

namespace {
void createFolders(const fs::path& dir, const std::string& flag, const std::string& what) {
  if (dir.empty()) return;
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec || !fs::is_directory(dir))
    throw InputError(flag + " " + what + ": cannot create folder " + dir.string() + ": " +
                     (ec ? ec.message() : "a file of that name exists"));
}

void proveWritable(const fs::path& file, const std::string& flag, const std::string& shown) {
  std::error_code ec;
  const bool existed = fs::exists(file, ec);
  if (existed && fs::is_directory(file, ec))
    throw InputError(flag + " " + shown + ": is a folder, not a file");
  std::FILE* f = std::fopen(file.c_str(), "ab");  // "a": never truncates an existing file
  if (!f) throw InputError(flag + " " + shown + ": cannot be written");
  std::fclose(f);
  if (!existed) fs::remove(file, ec);
}
}  // namespace

void prepareOutputFile(const std::string& path, const std::string& flag, bool replace) {
  if (path.empty()) throw InputError(flag + ": empty path");
  std::error_code ec;
  if (!replace && fs::exists(path, ec) && !fs::is_directory(path, ec))
    throw InputError(flag + " " + path + ": the file exists (an earlier run's?); -f/--force replaces it");
  createFolders(fs::path(path).parent_path(), flag, path);
  proveWritable(path, flag, path);
}

void refuseSameFile(const std::string& path, const std::string& flag,
                    const std::vector<NamedPath>& others) {
  if (path.empty()) return;
  std::error_code ec;
  const fs::path a = fs::weakly_canonical(fs::absolute(path), ec);
  for (const NamedPath& o : others) {
    if (o.path.empty()) continue;
    std::error_code ec2, ec3;
    const fs::path b = fs::weakly_canonical(fs::absolute(o.path), ec2);
    const bool same = (!ec && !ec2 && a == b) || fs::equivalent(path, o.path, ec3);
    if (same)
      throw InputError(flag + " " + path + ": the same file as " + o.name + " (" + o.path +
                       "); an output never overwrites it");
  }
}

void prepareOutputDir(const std::string& dir, const std::string& flag) {
  if (dir.empty()) throw InputError(flag + ": empty path");
  createFolders(dir, flag, dir);
  proveWritable(fs::path(dir) / ".startracker-write-test", flag, dir);
}

PendingOutput::PendingOutput(std::string path) : path_(std::move(path)) {
  const fs::path p(path_);
  // The extension stays last: writers that choose a format by it (OpenCV's FileStorage,
  // cfitsio) write the same file under the temporary name.
  temp_ = (p.parent_path() / (".partial-" + p.filename().string())).string();
}

PendingOutput::~PendingOutput() {
  if (committed_) return;
  std::error_code ec;
  fs::remove(temp_, ec);
}

void PendingOutput::commit() {
  if (committed_) return;
  std::error_code ec;
  fs::rename(temp_, path_, ec);
  if (ec) throw InputError(path_ + ": cannot be written (renaming " + temp_ + ": " + ec.message() + ")");
  committed_ = true;
}

void writeFileAtomically(const std::string& path, const char* data, std::size_t size) {
  PendingOutput out(path);
  {
    std::FILE* f = std::fopen(out.tempPath().c_str(), "wb");
    if (!f) throw InputError(path + ": cannot be written");
    const bool ok = std::fwrite(data, 1, size, f) == size;
    if (std::fclose(f) != 0 || !ok) throw InputError(path + ": write failed (disk full?)");
  }
  out.commit();
}

}  // namespace st

#include "tests/fuzz/targets/fuzz_io.hpp"

#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace st::fuzz {

namespace {

/// A private folder per process, in memory when /dev/shm exists (a million inputs are a
/// million file writes).
const std::string& scratchDir() {
  static const std::string dir = [] {
    const char* base = std::getenv("ST_FUZZ_TMPDIR");
    std::string root = base ? base : (std::filesystem::is_directory("/dev/shm") ? "/dev/shm" : "/tmp");
    std::string tmpl = root + "/st_fuzz_XXXXXX";
    if (!mkdtemp(tmpl.data())) throw std::runtime_error("fuzz: cannot create a folder in " + root);
    return tmpl;
  }();
  return dir;
}

/// Removes the scratch folder at exit (libFuzzer exits through exit()).
struct Cleanup {
  ~Cleanup() {
    std::error_code ec;
    if (!dir.empty()) std::filesystem::remove_all(dir, ec);
  }
  std::string dir;
} cleanup;

}  // namespace

std::string writeInput(const std::uint8_t* data, std::size_t size, const std::string& suffix) {
  if (cleanup.dir.empty()) cleanup.dir = scratchDir();
  const std::string path = scratchDir() + "/input" + suffix;
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
  if (!out) throw std::runtime_error("fuzz: cannot write " + path);
  return path;
}

Split splitSelector(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return {0, data, 0};
  return {data[0], data + 1, size - 1};
}

}  // namespace st::fuzz

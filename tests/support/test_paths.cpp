#include <sstream>
#include <fstream>
#include <algorithm>
#include "tests/support/test_paths.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

namespace st::test {

std::string repoDir() { return ST_REPO_DIR; }

std::string sharedDataDir() {
  if (const char* env = std::getenv("ST_SHARED_DATA_DIR")) return env;
  return ST_SHARED_DATA_DIR;
}

std::string hipparcosSubsetPath() { return repoDir() + "/catalog/data/hip_main_v6.6.dat.gz"; }

std::string tetra3ImageDir() { return repoDir() + "/tests/data/tetra3"; }

namespace {
/// The files of `dir` ending in `extension`, sorted by name.
std::vector<std::string> filesIn(const std::string& dir, const std::string& extension) {
  std::vector<std::string> out;
  for (const auto& e : std::filesystem::directory_iterator(dir))
    if (e.path().extension() == extension) out.push_back(e.path().string());
  std::sort(out.begin(), out.end());
  return out;
}
}  // namespace

std::vector<std::string> tetra3Frames() { return filesIn(tetra3ImageDir(), ".tiff"); }

std::string swarmImageDir() { return repoDir() + "/tests/data/swarm"; }

std::vector<std::string> swarmFrames() { return filesIn(swarmImageDir(), ".png"); }

std::string bsc5Path() { return repoDir() + "/catalog/data/bsc5"; }

std::string makeTempDir(const std::string& tag) {
  namespace fs = std::filesystem;
  std::string templ = (fs::temp_directory_path() / ("st_" + tag + "_XXXXXX")).string();
  if (!mkdtemp(templ.data())) return (fs::temp_directory_path() / ("st_" + tag)).string();
  return templ;
}

std::string startrackerExe() { return ST_STARTRACKER_EXE_PATH; }

int runCommand(const std::string& cmd, std::string* output) {
  FILE* pipe = popen((cmd + " 2>&1").c_str(), "r");
  if (!pipe) return -1;
  std::array<char, 4096> buf{};
  std::string out;
  while (std::fgets(buf.data(), buf.size(), pipe)) out += buf.data();
  const int status = pclose(pipe);
  if (output) *output = out;
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string fileBytes(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

}  // namespace st::test

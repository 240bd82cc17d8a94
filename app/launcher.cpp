// `startracker`: a launcher that links no library of the project, so that it starts in about
// a millisecond. It answers `startracker --version` itself and execs startracker-cli (found
// next to it) with the same argv for everything else. The program proper links OpenCV and
// MRPT: some 330 shared libraries that the dynamic loader needs about 0.4 s to relocate
// (measured with LD_DEBUG=statistics), which a script asking for the version, or a batch of
// processes, should not pay.
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <string>

namespace {

/// True for `startracker --version` with no command (the flags allowed before a command,
/// -v/-q/--version, take no value, so any other word is the command).
bool versionOnly(int argc, char** argv) {
  bool version = false;
  for (int i = 1; i < argc; ++i) {
    if (argv[i][0] != '-') return false;
    if (std::strcmp(argv[i], "--version") == 0) version = true;
    if (std::strcmp(argv[i], "--help") == 0 || std::strcmp(argv[i], "-h") == 0) return false;
  }
  return version;
}

std::string siblingPath(const char* argv0, const char* name) {
  char self[4096];
  const ssize_t n = ::readlink("/proc/self/exe", self, sizeof self - 1);
  std::string dir = n > 0 ? std::string(self, std::size_t(n)) : std::string(argv0);
  const auto slash = dir.rfind('/');
  dir = slash == std::string::npos ? "." : dir.substr(0, slash);
  return dir + "/" + name;
}

}  // namespace

int main(int argc, char** argv) {
  if (versionOnly(argc, argv)) {
    std::printf("startracker %s\n", ST_VERSION);
    return 0;
  }
  const std::string cli = siblingPath(argv[0], "startracker-cli");
  ::execv(cli.c_str(), argv);
  // No st::log here: linking it would defeat the launcher; this is its one message.
  std::fprintf(stderr, "error: cannot run %s: %s\n", cli.c_str(), std::strerror(errno));
  return 1;
}

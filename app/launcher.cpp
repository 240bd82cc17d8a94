// `startracker`: a launcher that links no library of the project. It execs the program that
// serves the command: `solve` -> startracker-solve (the plate-solving stage only: OpenCV
// core/imgproc, cfitsio and the image codecs, no MRPT), everything else -> startracker-cli
// (MRPT's rawlogs, sensors, simulator and plots: some 330 shared libraries that the dynamic
// loader needs about 0.4 s to map and relocate). `startracker --version` is answered here.
#include <cstdio>
#include <cstring>

#include "app/sibling_exec.hpp"

namespace {

/// The command word: the first argument that is not a flag (the flags allowed before a
/// command, -v/-q/--version/--help, take no value). nullptr when there is none.
const char* commandWord(int argc, char** argv) {
  for (int i = 1; i < argc; ++i)
    if (argv[i][0] != '-') return argv[i];
  return nullptr;
}

bool hasFlag(int argc, char** argv, const char* flag) {
  for (int i = 1; i < argc; ++i)
    if (std::strcmp(argv[i], flag) == 0) return true;
  return false;
}

}  // namespace

int main(int argc, char** argv) {
  const char* command = commandWord(argc, argv);
  if (!command && hasFlag(argc, argv, "--version") && !hasFlag(argc, argv, "--help") &&
      !hasFlag(argc, argv, "-h")) {
    std::printf("startracker %s\n", ST_VERSION);
    return 0;
  }
  const bool solve = command && std::strcmp(command, "solve") == 0;
  return st::app::execSibling(solve ? "startracker-solve" : "startracker-cli", argv);
}

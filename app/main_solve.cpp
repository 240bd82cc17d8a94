// startracker-solve: `startracker solve` alone, on the plate-solving stage (no MRPT, no OpenCV
// imgcodecs), so that one process per frame starts in milliseconds. What that stage does not
// read itself is handed to startracker-cli, which serves the same command with every reader:
// an MRPT .ini camera file (MRPT's config reader) and image formats other than PNG, JPEG,
// TIFF, binary PNM and FITS (OpenCV's imgcodecs: BMP, WebP, JPEG 2000, ...).
#include <algorithm>
#include <cctype>
#include <cstring>
#include <string>

#include "app/cli_main.hpp"
#include "app/sibling_exec.hpp"
#include "imageio/image_codecs.hpp"
#include "sensors/camera/camera_model.hpp"

namespace {

std::string lowerExtension(const std::string& path) {
  const auto dot = path.rfind('.');
  if (dot == std::string::npos || path.find('/', dot) != std::string::npos) return "";
  std::string e = path.substr(dot);
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return std::tolower(c); });
  return e;
}

/// An image only OpenCV's imgcodecs reads: by its extension, or a .pgm/.ppm/.pnm whose magic
/// is not the binary P5/P6 the stage's own reader takes.
bool needsOpenCvReader(const std::string& arg) {
  static const char* kOnlyOpenCv[] = {".bmp", ".dib", ".webp", ".jp2", ".exr", ".hdr", ".pic",
                                      ".ras", ".sr",  ".pbm",  ".pfm", ".pxm"};
  const std::string e = lowerExtension(arg);
  for (const char* x : kOnlyOpenCv)
    if (e == x) return true;
  if (e == ".pgm" || e == ".ppm" || e == ".pnm") {
    try {
      return st::imageio::sniffFormat(arg) == st::imageio::Format::kOther;
    } catch (...) {
      return false;  // unreadable: the command says so itself
    }
  }
  return false;
}

bool needsFullProgram(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--camera" && i + 1 < argc && st::isIniCameraPath(argv[i + 1])) return true;
    if (a.rfind("--camera=", 0) == 0 && st::isIniCameraPath(a.substr(9))) return true;
    if (needsOpenCvReader(a)) return true;
  }
  return false;
}

void addOnlySolve(CLI::App& root, st::app::CommandRun& run) { st::app::addSolveCommand(root, run); }

}  // namespace

int main(int argc, char** argv) {
  if (needsFullProgram(argc, argv)) return st::app::execSibling("startracker-cli", argv);
  return st::app::runCommandLine(argc, argv, addOnlySolve);
}

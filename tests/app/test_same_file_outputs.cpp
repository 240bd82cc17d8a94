// Issue 39, "data lost": an output that names a file the command reads (or another output)
// is refused before any work, naming the flag, exit 2, and the file is left as it was. Each
// case once lost data: `replay X.rawlog --csv X.rawlog` truncated the recording to a CSV,
// `solve x.png --annotate x.png` overwrote the image, `--wcs F --annotate F` lost the WCS,
// `calibrate DIR -o DIR/frame`, `dark DIR -o DIR/frame` and `catalog build --catalog C -o C`
// overwrote an input.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "tests/app/test_cli_run.hpp"

namespace st {
namespace {

namespace fs = std::filesystem;

/// Runs `args` in `dir`; expects exit 2 naming `flag` and "same file", and `kept` unchanged.
void expectRefused(const std::string& args, const std::string& dir, const std::string& flag,
                   const std::string& kept) {
  const std::string before = test::fileBytes(kept);
  ASSERT_FALSE(before.empty()) << kept;
  const test::CliRun r = test::runCli(args, dir);
  EXPECT_EQ(r.code, 2) << args << "\n" << r.err;
  EXPECT_NE(r.err.find(flag), std::string::npos) << args << "\n" << r.err;
  EXPECT_NE(r.err.find("same file"), std::string::npos) << args << "\n" << r.err;
  EXPECT_EQ(test::fileBytes(kept), before) << args << ": " << kept << " was changed";
}

TEST(SameFileOutputs, SolveAnnotateOrWcsOverAnInputOrEachOtherIsRefused) {
  const std::string dir = test::makeTempDir("same_file_solve");
  fs::copy_file(test::tetra3Frames().front(), dir + "/x.tiff");
  fs::copy_file(test::swarmFrames().front(), dir + "/s.png");
  expectRefused("solve s.png --fov-deg 18.4 --pixel-aspect 2 --annotate s.png", dir,
                "--annotate", dir + "/s.png");
  expectRefused("solve x.tiff --fov-deg 11.4 --wcs ./x.tiff", dir, "--wcs", dir + "/x.tiff");
  std::ofstream(dir + "/f.png") << "an earlier file";
  expectRefused("solve x.tiff --fov-deg 11.4 --wcs f.png --annotate f.png", dir, "--wcs",
                dir + "/f.png");
}

TEST(SameFileOutputs, ReplayCsvOverTheRecordingOrTheOutputIsRefused) {
  const std::string dir = test::makeTempDir("same_file_replay");
  fs::copy_file(test::repoDir() + "/rawlogs/hold.rawlog", dir + "/X.rawlog");
  fs::create_directory_symlink(test::repoDir() + "/rawlogs/hold_Images", dir + "/X_Images");
  expectRefused("replay X.rawlog --csv X.rawlog", dir, "--csv", dir + "/X.rawlog");
  std::ofstream(dir + "/o") << "an earlier output";
  expectRefused("replay X.rawlog -o o --csv o", dir, "--csv", dir + "/o");
}

TEST(SameFileOutputs, CalibrateDarkAndCatalogOverAnInputAreRefused) {
  const std::string dir = test::makeTempDir("same_file_inputs");
  fs::create_directory(dir + "/frames");
  for (int k = 0; k < 3; ++k)
    fs::copy_file(test::tetra3Frames()[static_cast<std::size_t>(k)],
                  dir + "/frames/f" + std::to_string(k) + ".tiff");
  expectRefused("calibrate frames --fov-deg 11.4 -o frames/f0.tiff", dir, "-o",
                dir + "/frames/f0.tiff");
  expectRefused("dark frames -o frames/f1.tiff", dir, "-o", dir + "/frames/f1.tiff");
  fs::copy_file(test::hipparcosSubsetPath(), dir + "/hip.dat.gz");
  expectRefused("catalog build --catalog hip.dat.gz --fov-deg 10 -o hip.dat.gz", dir, "--output",
                dir + "/hip.dat.gz");
}

}  // namespace
}  // namespace st

// The thirty real frames of ESA's Swarm star cameras (issue 34; tests/data/swarm), solved by
// the program as a user runs it, against astrometry.net's solutions beside them (an outside
// reference, read with tests/support/wcs_reference.hpp): the sky direction of each frame's
// centre pixel within 60" (the acceptance), with the nominal camera file of the binned
// geometry and with --pixel-aspect 2 and no camera. No wrong attitude on any frame.
//
// A reference is taken as sound when the catalog stars it places in the image (V <= 5.5,
// 3 px inside) have light there (a pixel > 30 ADU within 2 px), allowing one miss (a star
// on a defect or a merged pair): that judges astrometry.net's order-2 SIP solution by the
// image alone, not by ours. Three references fail it (2-4 of 12-15 bright stars placed
// where there is no light, up to 14 px off at the edge): there the centre is compared too
// but a difference is not called wrong; the solution must instead hold its own stars (at
// least 20 matched, RMS under 0.5 px).
#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "catalog/star_catalog.hpp"
#include "common/conventions.hpp"
#include "tests/app/test_cli_run.hpp"
#include "tests/support/wcs_reference.hpp"

namespace st {
namespace {

constexpr double kWithinArcsec = 60;

std::string wcsOf(const std::string& png) {
  return std::filesystem::path(png).replace_extension(".wcs").string();
}

bool soundReference(const std::string& png) {
  static const StarCatalog cat = loadHipparcos(test::hipparcosSubsetPath());
  const cv::Mat img = cv::imread(png, cv::IMREAD_UNCHANGED);
  const test::WcsReference w(wcsOf(png), true);
  int placed = 0, missed = 0;
  for (const CatalogEntry& e : cat.entries) {
    if (e.vmag > 5.5) continue;
    double x = 0, y = 0;
    if (!w.skyToPixel(e.ra, e.dec, x, y) || x < 3 || y < 3 || x > img.cols - 4 || y > img.rows - 4)
      continue;
    ++placed;
    const int cx = static_cast<int>(std::lround(x)), cy = static_cast<int>(std::lround(y));
    double top = 0;
    cv::minMaxLoc(img(cv::Rect(cx - 2, cy - 2, 5, 5)), nullptr, &top);
    missed += top <= 30;
  }
  return placed > 0 && missed <= 1;
}

struct Tally {
  int frames = 0, within = 0, wrong = 0, solved = 0;
};

Tally solveAll(const std::string& camera_args) {
  const test::CliRun r = test::runCli("solve '" + test::swarmImageDir() + "' " + camera_args +
                                      " --no-aberration --json -q --threads 2");
  Tally t;
  std::istringstream lines(r.out);
  std::string line;
  while (std::getline(lines, line)) {
    const auto j = nlohmann::json::parse(line);
    const std::string png = j.at("image");
    ++t.frames;
    const std::string name = std::filesystem::path(png).filename().string();
    if (!j.at("solved").get<bool>()) {
      std::printf("  %s: not solved: %s\n", name.c_str(), j.value("reason", "").c_str());
      continue;
    }
    ++t.solved;
    const test::WcsReference w(wcsOf(png), true);
    double ra = 0, dec = 0;
    w.pixelToSky(375.5, 144.5, ra, dec);
    const double d = test::separationArcsec(ra, dec, deg2rad(j.at("centre_ra_deg").get<double>()),
                                            deg2rad(j.at("centre_dec_deg").get<double>()));
    const bool sound = soundReference(png);
    t.within += d <= kWithinArcsec;
    if (d > kWithinArcsec) {
      if (sound) ++t.wrong;
      else {
        EXPECT_GE(j.at("stars_matched").get<int>(), 20) << name;
        EXPECT_LT(j.at("rms_residual_px").get<double>(), 0.5) << name;
      }
    }
    std::printf("  %s: %.1f\" from the reference%s, %d stars\n", name.c_str(), d,
                sound ? "" : " (unsound reference)", j.at("stars_matched").get<int>());
  }
  std::printf("%s: %d of %d within 60\", %d wrong\n", camera_args.c_str(), t.within, t.frames,
              t.wrong);
  return t;
}

TEST(SwarmFrames, SlowNominalBinnedCameraFileSolvesTwentyNineOfThirty) {
  const Tally t = solveAll("--camera '" + test::repoDir() + "/docs/inflight/swarm_str.yaml'");
  EXPECT_EQ(t.frames, 30);
  EXPECT_GE(t.within, 29);
  EXPECT_EQ(t.wrong, 0);
}

// The width range astrometry.net was given for these frames (14-22 deg); the default range
// (5-30 deg) gives the same 28 of 30 in 1-4 s per frame instead of ~0.4 s.
TEST(SwarmFrames, SlowPixelAspectTwoWithoutCameraSolvesTwentySevenOfThirty) {
  const Tally t = solveAll("--pixel-aspect 2 --fov-range 14 22");
  EXPECT_EQ(t.frames, 30);
  EXPECT_GE(t.within, 27);
  EXPECT_EQ(t.wrong, 0);
}

// One head's frames as a sequence (issue 34): MRPT's image_dir grabber plays the ten StrA
// frames into `live` (the nominal binned camera, the epoch of the frames), which records a
// rawlog that `replay` runs again. Unrelated frames (10 minutes apart on orbit): every one
// solved lost-in-space, in live (windows that find nothing re-acquire in the frame) and in
// replay.
TEST(SwarmFrames, SlowOneHeadLiveThenReplayedSolvesEveryFrameLostInSpace) {
  const std::string dir = test::makeTempDir("swarm_live");
  std::filesystem::create_directories(dir + "/frames");
  int k = 0;
  for (const std::string& f : test::swarmFrames())
    if (f.find("SWA_StrA_") != std::string::npos)
      std::filesystem::create_symlink(f, dir + "/frames/frame_0" + std::to_string(k++) + ".png");
  ASSERT_EQ(k, 10);
  std::filesystem::copy_file(test::repoDir() + "/docs/inflight/swarm_str.yaml",
                             dir + "/frames/cam.yaml");
  std::ifstream example(test::repoDir() + "/rawlogs/live_camera_image_dir.ini");
  std::stringstream text;
  text << example.rdbuf();
  std::string ini = text.str();
  for (const auto& [from, to] : std::vector<std::pair<std::string, std::string>>{
           {"frame_%02d.tiff", "frame_%02d.png"},
           {"end_index             = 7", "end_index             = 9"},
           {"epoch_jyear    = 2019.57", "epoch_jyear    = 2014.8"}}) {
    const std::size_t at = ini.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    ini.replace(at, from.size(), to);
  }
  std::ofstream(dir + "/live.ini") << ini;
  const test::CliRun live = test::runCli("live live.ini -o strA.rawlog --duration 5", dir);
  ASSERT_EQ(live.code, 0) << live.err;
  const std::string both = live.out + live.err;
  EXPECT_NE(both.find("star tracker: 10 frames, 10 solved"), std::string::npos) << both;
  const test::CliRun replay = test::runCli("replay strA.rawlog -q", dir);
  ASSERT_EQ(replay.code, 0) << replay.err;
  EXPECT_NE(replay.out.find("frames: 10, solved 100.0 %, lost-in-space 10"), std::string::npos)
      << replay.out;
}

// The reference test itself has teeth: a WCS shifted by 5 px is unsound.
TEST(SwarmFrames, ShiftedReferenceIsUnsound) {
  const std::string png = test::swarmFrames().front();
  ASSERT_TRUE(soundReference(png));
  const std::string dir = test::makeTempDir("swarm_ref");
  const std::string moved = dir + "/" + std::filesystem::path(png).filename().string();
  std::filesystem::copy_file(png, moved);
  std::ifstream in(wcsOf(png), std::ios::binary);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::size_t at = text.find("CRPIX1  =");
  ASSERT_NE(at, std::string::npos);
  const double crpix1 = std::stod(text.substr(at + 10, 20));
  char card[81];
  std::snprintf(card, sizeof card, "CRPIX1  = %20.8f / shifted by the test", crpix1 + 5);
  text.replace(at, 80, std::string(card) + std::string(80 - std::strlen(card), ' '));
  std::ofstream(wcsOf(moved), std::ios::binary) << text;
  EXPECT_FALSE(soundReference(moved));
}

}  // namespace
}  // namespace st

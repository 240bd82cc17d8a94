// `startracker dark` (seed 004 sec. 4.1: the dark image is the per-pixel median of several
// frames) and its two users, `solve --dark` and the tracker key detect_dark_file.
// The scene: a real tetra3 frame with a fixed pattern of warm pixel clusters added (PSF-sized,
// bright: the detector cannot tell them from stars by shape); five dark exposures hold the
// same clusters, one of them also a cosmic ray.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include <mrpt/config/CConfigFileMemory.h>
#include <opencv2/imgcodecs.hpp>

#include "common/errors.hpp"
#include "config/ini_reader.hpp"
#include "sensors/detect/dark_frame.hpp"
#include "sensors/mrpt/pipeline_ini.hpp"
#include "sensors/sim/psf.hpp"
#include "tests/app/solve_cli_util.hpp"
#include "tests/app/test_cli_run.hpp"

namespace st {
namespace {

/// Median and robust sigma (1.4826 MAD) of a 16-bit image.
std::pair<double, double> medianSigma(const cv::Mat& img) {
  std::vector<uint16_t> v(img.begin<uint16_t>(), img.end<uint16_t>());
  auto mid = v.begin() + v.size() / 2;
  std::nth_element(v.begin(), mid, v.end());
  const double med = *mid;
  std::vector<double> d(v.size());
  std::transform(v.begin(), v.end(), d.begin(), [&](uint16_t x) { return std::abs(x - med); });
  auto dm = d.begin() + d.size() / 2;
  std::nth_element(d.begin(), dm, d.end());
  return {med, 1.4826 * *dm};
}

struct DarkScene {
  std::string dir, frame, clean, dark_files;
  std::vector<cv::Point> warm;
  cv::Point cosmic{700, 500};
};

/// Writes clean.tiff (the tetra3 frame), frame.tiff (with 25 warm clusters) and five darks.
DarkScene makeScene() {
  DarkScene s;
  s.dir = test::makeTempDir("dark_cli");
  const cv::Mat clean = cv::imread(test::tetra3Frame(), cv::IMREAD_UNCHANGED);
  EXPECT_EQ(clean.type(), CV_16UC1);
  const auto [med, sigma] = medianSigma(clean);
  // Warm clusters as bright as a mid-bright star of the frame: 60 sigma at the peak.
  const double peak = 60 * std::max(sigma, 1.0), psf = 1.2;
  const double flux = peak * 2 * CV_PI * psf * psf;
  cv::Mat warm_e = cv::Mat::zeros(clean.size(), CV_64F);
  std::mt19937_64 rng(7);
  std::uniform_int_distribution<int> ux(30, clean.cols - 31), uy(30, clean.rows - 31);
  for (int i = 0; i < 25; ++i) {
    s.warm.emplace_back(ux(rng), uy(rng));
    addGaussianStar(warm_e, Vec2(s.warm.back().x + 0.3, s.warm.back().y + 0.6), flux, psf);
  }
  cv::Mat frame_d;
  clean.convertTo(frame_d, CV_64F);
  frame_d += warm_e;
  cv::Mat frame;
  frame_d.convertTo(frame, CV_16U);
  s.clean = s.dir + "/clean.tiff";
  s.frame = s.dir + "/frame.tiff";
  cv::imwrite(s.clean, clean);
  cv::imwrite(s.frame, frame);
  std::normal_distribution<double> noise(0.0, 1.0);
  for (int k = 0; k < 5; ++k) {
    cv::Mat d(clean.size(), CV_16U);
    for (int y = 0; y < d.rows; ++y)
      for (int x = 0; x < d.cols; ++x)
        d.at<uint16_t>(y, x) =
            cv::saturate_cast<uint16_t>(warm_e.at<double>(y, x) + 2 + noise(rng));
    if (k == 2)  // a cosmic ray: a short bright track in one dark only
      for (int t = 0; t < 4; ++t) d.at<uint16_t>(s.cosmic.y, s.cosmic.x + t) = 40000;
    const std::string f = s.dir + "/dark" + std::to_string(k) + ".png";
    cv::imwrite(f, d);
    s.dark_files += " " + f;
  }
  return s;
}

TEST(DarkCommand, MedianDarkRemovesWarmClustersAndCosmicRay) {
  const DarkScene s = makeScene();
  const std::string out = s.dir + "/master/dark.fits";
  const test::CliRun r = test::runCli("dark" + s.dark_files + " -o " + out);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("median of 5 frames (1024x768 16-bit)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("hot pixels"), std::string::npos) << r.out;
  const cv::Mat dark = readDarkFrame(out);
  ASSERT_EQ(dark.type(), CV_16UC1);
  // The cosmic ray is in one frame of five: the median holds the bias there.
  for (int t = 0; t < 4; ++t) EXPECT_LE(dark.at<uint16_t>(s.cosmic.y, s.cosmic.x + t), 6);
  // The warm clusters are in all five: the median keeps them.
  for (const auto& p : s.warm) EXPECT_GT(dark.at<uint16_t>(p.y, p.x), 100) << p;

  // Solving: without the dark the warm clusters are detected as stars; with it they are not,
  // and the frame solves to the attitude of the clean frame.
  const test::SolveRun clean = test::solveJson(test::shellQuote(s.clean));
  const test::SolveRun without = test::solveJson(test::shellQuote(s.frame));
  const test::SolveRun with = test::solveJson(test::shellQuote(s.frame) + " --dark " + out);
  ASSERT_EQ(clean.rc, 0) << clean.stdout_text;
  ASSERT_EQ(with.rc, 0) << with.stdout_text;
  const int n_clean = clean.json.at("stars_detected").get<int>();
  const int n_with = with.json.at("stars_detected").get<int>();
  const int n_without = without.json.is_null() ? 0 : without.json.value("stars_detected", 0);
  std::printf("stars detected: clean %d, with the dark %d, without %d\n", n_clean, n_with,
              n_without);
  EXPECT_GE(n_without, n_clean + 15) << "the warm clusters should pass detection";
  EXPECT_LE(std::abs(n_with - n_clean), 2);
  EXPECT_LT(test::attitudeDifferenceArcsec(with.json, clean.json), 5.0);
}

TEST(DarkCommand, BadInputsExitTwoNamingTheFile) {
  const DarkScene s = makeScene();
  const std::string dir = s.dir;
  // Too few frames for a median.
  test::CliRun r = test::runCli("dark " + dir + "/dark0.png " + dir + "/dark1.png -o d.fits");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("at least 3"), std::string::npos) << r.err;
  // A frame of another size, named.
  cv::imwrite(dir + "/small.png", cv::Mat(64, 80, CV_16U, cv::Scalar(3)));
  r = test::runCli("dark" + s.dark_files + " " + dir + "/small.png -o d.fits");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("small.png: 80x64 16-bit differs from the first dark frame"),
            std::string::npos) << r.err;
  // Another depth, named.
  cv::imwrite(dir + "/eight.png", cv::Mat(768, 1024, CV_8U, cv::Scalar(3)));
  r = test::runCli("dark" + s.dark_files + " " + dir + "/eight.png -o d.fits");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("eight.png"), std::string::npos) << r.err;
  // A missing frame.
  r = test::runCli("dark" + s.dark_files + " " + dir + "/nope.png -o d.fits");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("nope.png"), std::string::npos) << r.err;
  // solve --dark: a missing file, and a dark of another size than the image.
  r = test::runCli("solve " + s.frame + " --dark " + dir + "/missing.fits");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("missing.fits"), std::string::npos) << r.err;
  r = test::runCli("solve " + s.frame + " --dark " + dir + "/small.png");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--dark " + dir + "/small.png: 80x64"), std::string::npos) << r.err;
  // A colour dark is refused by name.
  cv::imwrite(dir + "/colour.png", cv::Mat(768, 1024, CV_8UC3, cv::Scalar(1, 2, 3)));
  r = test::runCli("solve " + s.frame + " --dark " + dir + "/colour.png");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("colour.png: a dark frame is a mono"), std::string::npos) << r.err;
}

TEST(DarkCommand, TrackerKeyReadsTheDark) {
  const std::string dir = test::makeTempDir("dark_key");
  const cv::Mat d(40, 50, CV_16U, cv::Scalar(7));
  cv::imwrite(dir + "/d.png", d);
  mrpt::config::CConfigFileMemory cfg;
  cfg.write("pipeline", "detect_dark_file", dir + "/d.png");
  PipelineOptions o;
  readPipelineOptions(IniReader{cfg, "t.ini"}, "pipeline", o);
  ASSERT_EQ(o.tracker.detect.dark().size(), cv::Size(50, 40));
  EXPECT_EQ(o.tracker.detect.dark().at<uint16_t>(3, 4), 7);
  EXPECT_NE(pipelineIniSchema().print("pipeline", o).find("detect_dark_file = " + dir + "/d.png"),
            std::string::npos);
  // A missing file fails when the configuration is read, naming the key and the file.
  cfg.write("pipeline", "detect_dark_file", dir + "/none.fits");
  try {
    readPipelineOptions(IniReader{cfg, "t.ini"}, "pipeline", o);
    FAIL() << "a missing dark file was accepted";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("detect_dark_file"), std::string::npos) << m;
    EXPECT_NE(m.find("none.fits"), std::string::npos) << m;
  }
  // The dynamic-threshold keys read in the same section; a bad mode names its key.
  mrpt::config::CConfigFileMemory bad("[pipeline]\ndetect_threshold_mode = adaptive\n");
  try {
    readPipelineOptions(IniReader{bad, "t.ini"}, "pipeline", o);
    FAIL() << "detect_threshold_mode = adaptive was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("detect_threshold_mode"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace st

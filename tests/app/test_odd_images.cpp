// Issue 18, item 7: odd images given to `startracker solve` (oversize headers, zero size, 1xN
// strips, colour, 16-bit PNG, FITS with NaNs). Bad ones exit 2 with a message in the
// project's words naming the file (never OpenCV's assertion text); colour is converted to grey
// with an info line, 16-bit stays 16-bit, NaNs are background. Limits: app/image_io.hpp.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "tests/app/solve_cli_util.hpp"
#include "tests/app/test_cli_run.hpp"
#include "tests/support/test_paths.hpp"

namespace st {
namespace {

const char* kStamp = "2019-07-29T204726";  // the real frame's epoch, kept in every file name

std::string realFrame() {
  return test::tetra3ImageDir() + "/" + kStamp + "_Alt40_Azi-135_Try1.tiff";
}

void writeBytes(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}

/// An InputError's exit and words: 2, the file named, `words` said, no OpenCV text.
void expectRefused(const std::string& path, const std::string& words) {
  const test::CliRun r = test::runCli("solve --fov-deg 10 '" + path + "'");
  EXPECT_EQ(r.code, 2) << r.out << r.err;
  EXPECT_NE(r.err.find(path), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(words), std::string::npos) << r.err;
  for (const char* leak : {"OpenCV", "Assertion", "cv::", "error: (-", "imread_", "bad_alloc"})
    EXPECT_EQ(r.err.find(leak), std::string::npos) << leak << " in " << r.err;
}

/// Big-endian 32-bit.
std::string be32(std::uint32_t v) {
  return {char(v >> 24), char(v >> 16), char(v >> 8), char(v)};
}

/// PNG's CRC-32 of `bytes`.
std::uint32_t crc32(const std::string& bytes) {
  std::uint32_t c = 0xFFFFFFFFu;
  for (unsigned char b : bytes) {
    c ^= b;
    for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xEDB88320u & (0u - (c & 1u)));
  }
  return c ^ 0xFFFFFFFFu;
}

/// A PNG signature and a valid IHDR chunk claiming w x h 8-bit grey (no pixel data follows).
std::string pngHeader(std::uint32_t w, std::uint32_t h) {
  const std::string ihdr =
      "IHDR" + be32(w) + be32(h) + std::string("\x08\x00\x00\x00\x00", 5);
  return std::string("\x89PNG\r\n\x1a\n", 8) + be32(13) + ihdr + be32(crc32(ihdr));
}

/// A little-endian baseline TIFF header claiming w x h 8-bit grey, one strip, no data.
std::string tiffHeader(std::uint32_t w, std::uint32_t h) {
  auto le16 = [](std::uint16_t v) { return std::string{char(v), char(v >> 8)}; };
  auto le32 = [](std::uint32_t v) {
    return std::string{char(v), char(v >> 8), char(v >> 16), char(v >> 24)};
  };
  auto entry = [&](std::uint16_t tag, std::uint16_t type, std::uint32_t value) {
    return le16(tag) + le16(type) + le32(1) +
           (type == 3 ? le16(std::uint16_t(value)) + le16(0) : le32(value));
  };
  std::string t = "II" + le16(42) + le32(8) + le16(9);
  t += entry(256, 4, w) + entry(257, 4, h) + entry(258, 3, 8) + entry(259, 3, 1) +
       entry(262, 3, 1) + entry(273, 4, 200) + entry(277, 3, 1) + entry(278, 4, h) +
       entry(279, 4, w * h);
  t += le32(0);
  t.resize(256, '\0');
  return t;
}

/// A FITS file, BITPIX -32, of `img` (CV_32F) or of a header alone claiming w x h.
std::string fits(int w, int h, const cv::Mat* img) {
  std::string hdr;
  auto card = [&](const std::string& s) {
    std::string c = s;
    c.resize(80, ' ');
    hdr += c;
  };
  auto num = [](const char* key, long v) {
    char b[81];
    std::snprintf(b, sizeof b, "%-8s= %20ld", key, v);
    return std::string(b);
  };
  card("SIMPLE  =                    T");
  card(num("BITPIX", -32));
  card(num("NAXIS", 2));
  card(num("NAXIS1", w));
  card(num("NAXIS2", h));
  card(std::string("DATE-OBS= '") + "2019-07-29T20:47:26'");  // the real frame's epoch
  card("END");
  hdr.resize((hdr.size() + 2879) / 2880 * 2880, ' ');
  if (!img) return hdr + std::string(2880, '\0');
  std::string data;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      std::uint32_t u;
      const float v = img->at<float>(y, x);
      std::memcpy(&u, &v, 4);
      data += be32(u);
    }
  data.resize((data.size() + 2879) / 2880 * 2880, '\0');
  return hdr + data;
}

/// The real frame as 8-bit grey, written beside the test's files as the reference input.
cv::Mat realGrey() {
  cv::Mat grey = cv::imread(realFrame(), cv::IMREAD_GRAYSCALE);
  EXPECT_FALSE(grey.empty()) << realFrame();
  return grey;
}

/// `path` solves (exit 0) to the attitude of `reference` (the same pixels as a plain 8-bit
/// grey PNG), and stderr says `info` when given.
void expectSolvesLike(const std::string& reference, const std::string& path,
                      const std::string& info = "") {
  const test::SolveRun ref = test::solveJson("--fov-deg 11.4 '" + reference + "'");
  ASSERT_EQ(ref.rc, 0) << ref.stdout_text;
  const test::SolveRun r = test::solveJson("--fov-deg 11.4 '" + path + "'");
  ASSERT_EQ(r.rc, 0) << r.stdout_text;
  EXPECT_LT(test::attitudeDifferenceArcsec(ref.json, r.json), 1.0) << r.stdout_text;
  if (!info.empty()) {
    const test::CliRun c = test::runCli("solve --fov-deg 11.4 '" + path + "'");
    EXPECT_EQ(c.code, 0) << c.err;
    EXPECT_NE(c.err.find(info), std::string::npos) << c.err;
  }
}

TEST(OddImages, OversizeHeadersAreRefusedBeforeDecoding) {
  const std::string dir = test::makeTempDir("odd_oversize");
  // The case: a PGM claiming 100000 x 100000 (1e10 pixels).
  writeBytes(dir + "/huge.pgm", "P5\n100000 100000\n255\n" + std::string(64, '\0'));
  expectRefused(dir + "/huge.pgm", "too large");
  writeBytes(dir + "/huge.png", pngHeader(100000, 100000));
  expectRefused(dir + "/huge.png", "too large");
  // 20000 x 20000 = 4e8 pixels: under OpenCV's default limit (2^30), over ours; a TIFF is
  // not parsed here, OpenCV's limit (set to ours) refuses it.
  writeBytes(dir + "/huge.tiff", tiffHeader(20000, 20000));
  expectRefused(dir + "/huge.tiff", "too large");
  writeBytes(dir + "/huge.fits", fits(100000, 100000, nullptr));
  expectRefused(dir + "/huge.fits", "too large");
}

TEST(OddImages, ZeroSizeIsRefused) {
  const std::string dir = test::makeTempDir("odd_zero");
  writeBytes(dir + "/empty.png", "");
  expectRefused(dir + "/empty.png", "empty file");
  writeBytes(dir + "/zero.pgm", "P5\n0 0\n255\n");
  expectRefused(dir + "/zero.pgm", "zero size");
  writeBytes(dir + "/zero.png", pngHeader(0, 480));
  expectRefused(dir + "/zero.png", "zero size");
}

TEST(OddImages, OneByNStripsAreRefused) {
  const std::string dir = test::makeTempDir("odd_strip");
  cv::Mat strip(1, 500, CV_8UC1, cv::Scalar(20));
  strip.at<uint8_t>(0, 250) = 255;
  ASSERT_TRUE(cv::imwrite(dir + "/row.png", strip));
  expectRefused(dir + "/row.png", "too small");
  ASSERT_TRUE(cv::imwrite(dir + "/column.png", strip.t()));
  expectRefused(dir + "/column.png", "too small");
  ASSERT_TRUE(cv::imwrite(dir + "/tiny.png", cv::Mat(8, 8, CV_8UC1, cv::Scalar(10))));
  expectRefused(dir + "/tiny.png", "too small");
}

// A frame cut short (a partial download, a full disk) is refused naming the file, never
// solved from the grey padding a decoder would fill in (libjpeg only warns of it). The
// solve program decodes these formats itself (imageio/image_codecs.hpp).
TEST(OddImages, CutImagesAreRefusedNamingTheFile) {
  const std::string dir = test::makeTempDir("odd_cut");
  const cv::Mat grey = realGrey();
  // OpenCV writes a TIFF's directory after its strips: half of it has no directory.
  const std::vector<std::pair<std::string, std::string>> cases = {
      {".jpg", "truncated"}, {".png", "truncated"}, {".tiff", "not a readable TIFF"}};
  for (const auto& [ext, words] : cases) {
    SCOPED_TRACE(ext);
    const std::string whole = dir + "/" + kStamp + "_whole" + ext;
    ASSERT_TRUE(cv::imwrite(whole, grey));
    std::ifstream in(whole, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::string cut = dir + "/" + kStamp + "_cut" + ext;
    writeBytes(cut, bytes.substr(0, bytes.size() / 2));
    expectRefused(cut, words);
  }
}

// A format only OpenCV's imgcodecs reads (BMP) is handed to the program that links it: the
// same answer as the PNG of the same pixels.
TEST(OddImages, FormatsOnlyOpenCvReadsStillSolve) {
  const std::string dir = test::makeTempDir("odd_bmp");
  const cv::Mat grey = realGrey();
  const std::string png = dir + "/" + kStamp + "_ref.png", bmp = dir + "/" + kStamp + "_ref.bmp";
  ASSERT_TRUE(cv::imwrite(png, grey));
  ASSERT_TRUE(cv::imwrite(bmp, grey));
  expectSolvesLike(png, bmp, "");
}

TEST(OddImages, ColourIsConvertedToGreyAndSaysSo) {
  const std::string dir = test::makeTempDir("odd_colour");
  const cv::Mat grey = realGrey();
  const std::string ref = dir + "/" + kStamp + "_grey.png";
  ASSERT_TRUE(cv::imwrite(ref, grey));
  cv::Mat bgr, bgra;
  cv::cvtColor(grey, bgr, cv::COLOR_GRAY2BGR);
  cv::cvtColor(grey, bgra, cv::COLOR_GRAY2BGRA);
  const std::string p3 = dir + "/" + kStamp + "_bgr.png", p4 = dir + "/" + kStamp + "_bgra.png";
  ASSERT_TRUE(cv::imwrite(p3, bgr));
  ASSERT_TRUE(cv::imwrite(p4, bgra));
  expectSolvesLike(ref, p3, "colour image (3 channels) converted to grey");
  expectSolvesLike(ref, p4, "colour image (4 channels) converted to grey");
}

// Stars that exist only in the low 8 bits: background 2068 (8.08 x 256), noise sigma 3,
// peaks at most 100 above it; read as 8 bits (/256, rounded) the frame is one flat level 8.
TEST(OddImages, SixteenBitPngStaysSixteenBit) {
  const std::string dir = test::makeTempDir("odd_16bit");
  cv::Mat f(480, 640, CV_32F);
  cv::RNG rng(18);
  rng.fill(f, cv::RNG::NORMAL, 2068.0, 3.0);
  int stars = 0;
  for (int y = 40; y < 440; y += 80)
    for (int x = 40; x < 600; x += 80, ++stars) {
      const double amp = 60.0 + (stars % 5) * 10.0;  // 60..100 DN
      for (int dy = -5; dy <= 5; ++dy)
        for (int dx = -5; dx <= 5; ++dx)
          f.at<float>(y + dy, x + dx) += float(amp * std::exp(-(dx * dx + dy * dy) / 4.5));
    }
  cv::Mat g16;
  f.convertTo(g16, CV_16U);
  const std::string p = dir + "/" + kStamp + "_16bit.png";
  ASSERT_TRUE(cv::imwrite(p, g16));
  ASSERT_EQ(cv::imread(p, cv::IMREAD_UNCHANGED).depth(), CV_16U);
  {  // teeth: as 8 bits the frame is flat
    cv::Mat g8;
    g16.convertTo(g8, CV_8U, 1.0 / 256);
    double lo = 0, hi = 0;
    cv::minMaxLoc(g8, &lo, &hi);
    ASSERT_EQ(lo, hi);
  }
  const test::SolveRun r = test::solveJson("--fov-deg 10 '" + p + "'");
  ASSERT_TRUE(r.json.is_object()) << r.stdout_text;
  ASSERT_TRUE(r.json.contains("stars_detected")) << r.stdout_text;
  EXPECT_GE(r.json["stars_detected"].get<int>(), stars * 9 / 10) << r.stdout_text;
}

TEST(OddImages, FitsNaNsAreBackground) {
  const std::string dir = test::makeTempDir("odd_fits_nan");
  const cv::Mat grey = realGrey();
  const std::string ref = dir + "/" + kStamp + "_grey.png";
  ASSERT_TRUE(cv::imwrite(ref, grey));
  cv::Mat f;
  grey.convertTo(f, CV_32F, 1.0, 1000.0);  // a sky background far from 0
  const float nan = std::numeric_limits<float>::quiet_NaN();
  // A masked corner, a dead column and scattered dead pixels.
  f(cv::Rect(0, 0, 60, 60)).setTo(nan);
  f.col(f.cols / 3).setTo(nan);
  for (int k = 0; k < 200; ++k) f.at<float>((k * 37) % f.rows, (k * 91) % f.cols) = nan;
  const std::string p = dir + "/" + kStamp + "_nan.fits";
  writeBytes(p, fits(f.cols, f.rows, &f));
  expectSolvesLike(ref, p, "treated as background");

  cv::Mat all(64, 64, CV_32F, cv::Scalar(nan));
  writeBytes(dir + "/all_nan.fits", fits(64, 64, &all));
  expectRefused(dir + "/all_nan.fits", "no finite pixels");
}

}  // namespace
}  // namespace st

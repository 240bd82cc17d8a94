// `solve` from a star list instead of an image (issue 21 item 10): the centroids of a real
// frame written as CSV (x,y,flux, 0-based) and as a FITS table (X,Y,FLUX, 1-based, IMAGEW /
// IMAGEH, as solve-field's xylist) give the image's attitude.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>

#include "sensors/detect/star_detector.hpp"
#include "tests/app/solve_cli_util.hpp"

namespace st {
namespace {

struct Detections {
  std::vector<Centroid> stars;
  int width = 0, height = 0;
};

Detections detectFrame() {
  const cv::Mat img = cv::imread(test::tetra3Frame(), cv::IMREAD_UNCHANGED);
  Detections d;
  d.width = img.cols;
  d.height = img.rows;
  d.stars = detectStars(img).stars;
  return d;
}

std::string writeCsv(const Detections& d, const std::string& dir) {
  const std::string path = dir + "/2019-07-29T204726_stars.csv";
  std::ofstream out(path);
  out << "x,y,flux\n";
  out.precision(10);
  // Faintest first: the solver must sort by flux, not trust the order.
  for (auto it = d.stars.rbegin(); it != d.stars.rend(); ++it)
    out << it->px.x() << "," << it->px.y() << "," << it->flux << "\n";
  return path;
}

/// One 80-character FITS header card.
std::string card(const std::string& key, const std::string& value) {
  std::string c = key;
  c.resize(8, ' ');
  if (!value.empty()) {
    std::string v = value;
    if (v[0] != '\'') v = std::string(20 - std::min<std::size_t>(20, v.size()), ' ') + v;
    c += "= " + v;
  }
  c.resize(80, ' ');
  return c;
}

void padBlock(std::string& s, char fill) { s.resize((s.size() + 2879) / 2880 * 2880, fill); }

void putBigEndian(std::string& s, float v) {
  uint32_t u;
  std::memcpy(&u, &v, 4);
  for (int shift = 24; shift >= 0; shift -= 8) s += char((u >> shift) & 0xff);
}

/// solve-field's xylist layout written by hand (FITS standard 4.0): an empty primary HDU and
/// a binary table X, Y, FLUX (float32, big-endian), pixels 1-based.
std::string writeFitsTable(const Detections& d, const std::string& dir) {
  std::string f = card("SIMPLE", "T") + card("BITPIX", "8") + card("NAXIS", "0") +
                  card("EXTEND", "T") + card("END", "");
  padBlock(f, ' ');
  const std::string n = std::to_string(d.stars.size());
  f += card("XTENSION", "'BINTABLE'") + card("BITPIX", "8") + card("NAXIS", "2") +
       card("NAXIS1", "12") + card("NAXIS2", n) + card("PCOUNT", "0") + card("GCOUNT", "1") +
       card("TFIELDS", "3") + card("TTYPE1", "'X       '") + card("TFORM1", "'E       '") +
       card("TTYPE2", "'Y       '") + card("TFORM2", "'E       '") +
       card("TTYPE3", "'FLUX    '") + card("TFORM3", "'E       '") +
       card("IMAGEW", std::to_string(d.width)) + card("IMAGEH", std::to_string(d.height)) +
       card("DATE-OBS", "'2019-07-29T20:47:26'") + card("END", "");
  padBlock(f, ' ');
  for (const Centroid& c : d.stars) {
    putBigEndian(f, float(c.px.x() + 1));  // FITS pixels are 1-based
    putBigEndian(f, float(c.px.y() + 1));
    putBigEndian(f, float(c.flux));
  }
  padBlock(f, '\0');
  const std::string path = dir + "/stars.xyls";
  std::ofstream(path, std::ios::binary) << f;
  return path;
}

TEST(SolveStarList, CsvGivesTheImagesAttitude) {
  const Detections d = detectFrame();
  const std::string csv = writeCsv(d, test::makeTempDir("solve_csv"));
  const auto img = test::solveJson("--fov-deg 11.4 " + test::tetra3Frame());
  const auto list = test::solveJson("--fov-deg 11.4 --width " + std::to_string(d.width) +
                                    " --height " + std::to_string(d.height) + " " + csv);
  ASSERT_EQ(img.rc, 0) << img.stdout_text;
  ASSERT_EQ(list.rc, 0) << list.stdout_text;
  EXPECT_EQ(list.json.at("input"), "star list");
  EXPECT_EQ(list.json.at("epoch_source"), "file name");
  // Same centroids (written with 10 digits): the same attitude within an arcsec.
  EXPECT_LT(test::attitudeDifferenceArcsec(img.json, list.json), 1.0);
}

TEST(SolveStarList, FitsTableGivesTheImagesAttitude) {
  const Detections d = detectFrame();
  const std::string xyls = writeFitsTable(d, test::makeTempDir("solve_xyls"));
  const auto img = test::solveJson("--fov-deg 11.4 " + test::tetra3Frame());
  const auto list = test::solveJson("--fov-deg 11.4 " + xyls);  // size from IMAGEW/IMAGEH
  ASSERT_EQ(img.rc, 0) << img.stdout_text;
  ASSERT_EQ(list.rc, 0) << list.stdout_text;
  EXPECT_EQ(list.json.at("epoch_source"), "DATE-OBS");
  // Float columns: positions rounded to ~3e-5 px, far below the 0.2 px residuals.
  EXPECT_LT(test::attitudeDifferenceArcsec(img.json, list.json), 3.0);
  // Named .fits, the table is told from an image by its content.
  const std::string fits = xyls.substr(0, xyls.size() - 5) + ".fits";
  std::filesystem::copy_file(xyls, fits);
  const auto named_fits = test::solveJson("--fov-deg 11.4 " + fits);
  ASSERT_EQ(named_fits.rc, 0) << named_fits.stdout_text;
  EXPECT_EQ(named_fits.json.at("input"), "star list");
}

TEST(SolveStarList, BadListsNameTheFileAndWhatIsMissing) {
  const std::string dir = test::makeTempDir("solve_csv_bad");
  std::ofstream(dir + "/nosize.csv") << "x,y,flux\n1,2,3\n4,5,6\n7,8,9\n";
  auto r = test::solveJson("--fov-deg 10 " + dir + "/nosize.csv");
  EXPECT_EQ(r.rc, 2) << r.stdout_text;
  EXPECT_NE(r.json.at("error").get<std::string>().find("--width"), std::string::npos);
  std::ofstream(dir + "/noheader.csv") << "1,2,3\n";
  r = test::solveJson("--fov-deg 10 --width 100 --height 100 " + dir + "/noheader.csv");
  EXPECT_EQ(r.rc, 2) << r.stdout_text;
  EXPECT_NE(r.json.at("error").get<std::string>().find("noheader.csv:1"), std::string::npos);
  std::ofstream(dir + "/badnum.csv") << "x,y,flux\n1,2,3\n4,abc,6\n";
  r = test::solveJson("--fov-deg 10 --width 100 --height 100 " + dir + "/badnum.csv");
  EXPECT_EQ(r.rc, 2) << r.stdout_text;
  EXPECT_NE(r.json.at("error").get<std::string>().find("badnum.csv:3"), std::string::npos);
}

}  // namespace
}  // namespace st

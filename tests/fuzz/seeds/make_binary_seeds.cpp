// Writes the binary seeds of tests/fuzz/corpus/ that are not cut from project files: tiny
// images of each format the loader reads (image/), and a FITS binary-table star list
// (star_list/). Each seed starts with its target's selector byte (tests/fuzz/targets/).
// Not part of the build; to regenerate, from the repository root:
//   g++ -std=c++17 tests/fuzz/seeds/make_binary_seeds.cpp $(pkg-config --cflags --libs opencv4) -o /tmp/seeds
//   /tmp/seeds tests/fuzz/corpus
#include <cstdint>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>

namespace {

std::string card(const std::string& key, const std::string& value) {
  std::string c = key;
  c.resize(8, ' ');
  if (key != "END") c += "= " + value;
  c.resize(80, ' ');
  return c;
}
void padBlock(std::string& s, char fill) { s.resize((s.size() + 2879) / 2880 * 2880, fill); }
void putBe32(std::string& s, std::uint32_t u) {
  for (int shift = 24; shift >= 0; shift -= 8) s += char((u >> shift) & 0xff);
}
void putFloat(std::string& s, float v) {
  std::uint32_t u;
  std::memcpy(&u, &v, 4);
  putBe32(s, u);
}
void save(const std::string& path, unsigned char selector, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << char(selector) << bytes;
}
std::string encode(const cv::Mat& img, const std::string& ext) {
  std::vector<unsigned char> buf;
  cv::imencode(ext, img, buf);
  return std::string(buf.begin(), buf.end());
}

}  // namespace

int main(int, char** argv) {
  const std::string out = argv[1];
  // A 16x16 (the loader's smallest) dark frame with two stars.
  cv::Mat img(16, 16, CV_8UC1, cv::Scalar(10));
  img.at<unsigned char>(4, 5) = 200;
  img.at<unsigned char>(11, 9) = 120;
  cv::Mat img16;
  img.convertTo(img16, CV_16U, 256);
  save(out + "/image/grey8.png", 0, encode(img, ".png"));
  save(out + "/image/grey16.png", 0, encode(img16, ".png"));
  save(out + "/image/grey8.jpg", 1, encode(img, ".jpg"));
  save(out + "/image/grey16.tif", 2, encode(img16, ".tif"));
  save(out + "/image/grey8.pgm", 3, encode(img, ".pgm"));
  // FITS primary image, 16-bit, with DATE-OBS.
  std::string fits = card("SIMPLE", "T") + card("BITPIX", "16") + card("NAXIS", "2") +
                     card("NAXIS1", "16") + card("NAXIS2", "16") +
                     card("DATE-OBS", "'2019-07-29T20:47:26'") + card("END", "");
  padBlock(fits, ' ');
  for (int r = 0; r < 16; ++r)
    for (int c = 0; c < 16; ++c) {
      const int v = img.at<unsigned char>(r, c) * 100;
      fits += char(v >> 8);
      fits += char(v & 0xff);
    }
  padBlock(fits, '\0');
  save(out + "/image/grey16.fits", 4, fits);
  // solve-field's xylist: empty primary HDU, binary table X, Y, FLUX (1-based pixels).
  std::string t = card("SIMPLE", "T") + card("BITPIX", "8") + card("NAXIS", "0") +
                  card("EXTEND", "T") + card("END", "");
  padBlock(t, ' ');
  t += card("XTENSION", "'BINTABLE'") + card("BITPIX", "8") + card("NAXIS", "2") +
       card("NAXIS1", "12") + card("NAXIS2", "3") + card("PCOUNT", "0") + card("GCOUNT", "1") +
       card("TFIELDS", "3") + card("TTYPE1", "'X       '") + card("TFORM1", "'E       '") +
       card("TTYPE2", "'Y       '") + card("TFORM2", "'E       '") +
       card("TTYPE3", "'FLUX    '") + card("TFORM3", "'E       '") + card("IMAGEW", "1024") +
       card("IMAGEH", "768") + card("DATE-OBS", "'2019-07-29T20:47:26'") + card("END", "");
  padBlock(t, ' ');
  for (float s : {1.f, 2.f, 3.f}) {
    putFloat(t, 100 * s + 0.5f);
    putFloat(t, 50 * s + 0.25f);
    putFloat(t, 1000 / s);
  }
  padBlock(t, '\0');
  save(out + "/star_list/xyls.xyls", 1, t);
  return 0;
}

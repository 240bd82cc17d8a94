#include "sensors/detect/dark_frame.hpp"

#include "imageio/fits.hpp"

#include "imageio/image_file.hpp"


#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>


#include "common/check.hpp"
#include "common/errors.hpp"
#include "sensors/detect/background.hpp"

namespace st {

namespace {

template <class T>
void medianOf(const std::vector<cv::Mat>& frames, cv::Mat& out) {
  const int n = static_cast<int>(frames.size());
  std::vector<T> v(static_cast<std::size_t>(n));
  std::vector<const T*> rows(static_cast<std::size_t>(n));
  for (int y = 0; y < out.rows; ++y) {
    for (int i = 0; i < n; ++i) rows[i] = frames[i].ptr<T>(y);
    T* o = out.ptr<T>(y);
    for (int x = 0; x < out.cols; ++x) {
      for (int i = 0; i < n; ++i) v[i] = rows[i][x];
      const auto mid = v.begin() + (n - 1) / 2;  // the lower middle for an even n
      std::nth_element(v.begin(), mid, v.end());
      o[x] = *mid;
    }
  }
}

bool endsWithFits(std::string p) {
  std::transform(p.begin(), p.end(), p.begin(), [](unsigned char c) { return std::tolower(c); });
  for (const std::string e : {".fits", ".fit", ".fts"})
    if (p.size() > e.size() && p.compare(p.size() - e.size(), e.size(), e) == 0) return true;
  return false;
}

cv::Mat readFitsDark(const std::string& path) {
  fitsfile* f = nullptr;
  int status = 0;
  const auto fail = [&](const std::string& what) {
    char msg[FLEN_STATUS] = {0};
    fits_get_errstatus(status, msg);
    int s2 = 0;
    if (f) fits_close_file(f, &s2);
    return InputError(path + ": " + what + " (cfitsio: " + msg + ")");
  };
  if (fits_open_image(&f, path.c_str(), READONLY, &status)) throw fail("cannot open the dark frame");
  int bitpix = 0, naxis = 0;
  long nax[2] = {0, 0};
  if (fits_get_img_param(f, 2, &bitpix, &naxis, nax, &status)) throw fail("bad FITS header");
  // BITPIX 16 with BZERO 32768 is unsigned 16-bit (cfitsio reports the equivalent type).
  int eq = 0;
  fits_get_img_equivtype(f, &eq, &status);
  if (naxis != 2 || nax[0] < 1 || nax[1] < 1 || (eq != BYTE_IMG && eq != USHORT_IMG))
    throw fail("a dark frame is a 2-D 8- or unsigned 16-bit image (NAXIS " +
               std::to_string(naxis) + ", BITPIX " + std::to_string(bitpix) + ")");
  cv::Mat img(static_cast<int>(nax[1]), static_cast<int>(nax[0]), eq == BYTE_IMG ? CV_8UC1 : CV_16UC1);
  long first[2] = {1, 1};
  int anynul = 0;
  if (fits_read_pix(f, eq == BYTE_IMG ? TBYTE : TUSHORT, first, nax[0] * nax[1], nullptr,
                    img.data, &anynul, &status))
    throw fail("cannot read the dark frame's pixels");
  fits_close_file(f, &status);
  return img;
}

}  // namespace

cv::Mat medianDark(const std::vector<cv::Mat>& frames) {
  if (frames.empty()) return {};
  cv::Mat out(frames[0].size(), frames[0].type());
  for (const auto& f : frames) ST_ASSERT(f.size() == out.size() && f.type() == out.type());
  if (out.type() == CV_8UC1)
    medianOf<uint8_t>(frames, out);
  else if (out.type() == CV_16UC1)
    medianOf<uint16_t>(frames, out);
  else
    ST_ASSERT(!"medianDark: 8- or 16-bit mono frames");
  return out;
}

DarkStats darkStats(const cv::Mat& dark, double k_sigma) {
  DarkStats s;
  if (dark.empty()) return s;
  cv::Mat d;
  dark.convertTo(d, CV_32F);
  s.mean = cv::mean(d)[0];
  // Robust, and read as grouped data: a median dark is whole numbers whose spread is often
  // below one ADU, where a plain MAD would be 0 and every pixel above the mean "hot".
  std::vector<float> v(d.begin<float>(), d.end<float>());
  double level = 0;
  robustLevelSigma(v, level, s.sigma);
  const double cut = s.mean + k_sigma * s.sigma;
  s.hot_pixels = static_cast<long>(cv::countNonZero(d > cut));
  return s;
}

cv::Mat readDarkFrame(const std::string& path) {
  if (endsWithFits(path)) return readFitsDark(path);
  const cv::Mat img = imageio::readImagePixels(path);
  if (img.channels() != 1 || (img.depth() != CV_8U && img.depth() != CV_16U))
    throw InputError(path + ": a dark frame is a mono 8- or 16-bit image (this is " +
                     cv::typeToString(img.type()) + ")");
  return img;
}

}  // namespace st

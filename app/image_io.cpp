#include "app/image_io.hpp"

#include <fitsio.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <regex>
#include <vector>

#include <opencv2/core/utils/logger.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "common/conventions.hpp"
#include "common/errors.hpp"

namespace st::app {

std::optional<double> parseIsoEpoch(const std::string& text) {
  static const std::regex re(
      R"((\d{4})-(\d{2})-(\d{2})(?:[T ](\d{2}):?(\d{2}):?(\d{2}(?:\.\d*)?))?)");
  std::smatch m;
  if (!std::regex_search(text, m, re)) return std::nullopt;
  std::tm tm{};
  tm.tm_year = std::stoi(m[1]) - 1900;
  tm.tm_mon = std::stoi(m[2]) - 1;
  tm.tm_mday = std::stoi(m[3]);
  double sec = 0;
  if (m[4].matched) {
    tm.tm_hour = std::stoi(m[4]);
    tm.tm_min = std::stoi(m[5]);
    sec = std::stod(m[6]);
  }
  if (tm.tm_mon < 0 || tm.tm_mon > 11 || tm.tm_mday < 1 || tm.tm_mday > 31) return std::nullopt;
  const double unix_s = static_cast<double>(timegm(&tm)) + sec;
  return julianYearFromUnixSeconds(unix_s);
}

namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

}  // namespace

bool isFitsPath(const std::string& path) {
  const std::string p = lower(path);
  for (const char* ext : {".fits", ".fit", ".fts", ".fits.gz", ".fit.gz", ".fts.gz"}) {
    const std::string e = ext;
    if (p.size() > e.size() && p.compare(p.size() - e.size(), e.size(), e) == 0) return true;
  }
  return false;
}

namespace {

LoadedImage loadFits(const std::string& path) {
  fitsfile* f = nullptr;
  int status = 0;
  auto fail = [&](const std::string& what) {
    char msg[FLEN_STATUS] = {0};
    fits_get_errstatus(status, msg);
    if (f) {
      int s2 = 0;
      fits_close_file(f, &s2);
    }
    return InputError(path + ": " + what + " (cfitsio: " + msg + ")");
  };
  if (fits_open_image(&f, path.c_str(), READONLY, &status)) throw fail("cannot open FITS image");
  int bitpix = 0, naxis = 0;
  long naxes[3] = {0, 0, 0};
  if (fits_get_img_param(f, 3, &bitpix, &naxis, naxes, &status)) throw fail("bad image header");
  if (naxis < 2 || naxes[0] <= 0 || naxes[1] <= 0)
    throw fail("not a 2-D image (NAXIS=" + std::to_string(naxis) + ")");
  const long w = naxes[0], h = naxes[1];
  std::vector<double> data(static_cast<std::size_t>(w * h));
  long first[3] = {1, 1, 1};
  int anynul = 0;
  if (fits_read_pix(f, TDOUBLE, first, w * h, nullptr, data.data(), &anynul, &status))
    throw fail("cannot read pixels");
  LoadedImage out;
  char date[FLEN_VALUE] = {0};
  int st2 = 0;
  if (!fits_read_key(f, TSTRING, "DATE-OBS", date, nullptr, &st2)) {
    out.epoch_jyear = parseIsoEpoch(date);
    if (out.epoch_jyear) out.epoch_source = "DATE-OBS";
  }
  fits_close_file(f, &status);
  // Integer data within 0..65535 is kept as is; anything else is scaled onto 16 bits.
  double lo = 1e300, hi = -1e300;
  bool integral = true;
  for (double v : data) {
    if (!std::isfinite(v)) continue;
    lo = std::min(lo, v), hi = std::max(hi, v);
    integral = integral && v == std::floor(v);
  }
  if (!(hi >= lo)) throw InputError(path + ": FITS image has no finite pixels");
  const bool keep = integral && lo >= 0 && hi <= 65535;
  const double scale = keep ? 1.0 : (hi > lo ? 65535.0 / (hi - lo) : 0.0);
  const double offset = keep ? 0.0 : lo;
  cv::Mat img(static_cast<int>(h), static_cast<int>(w), CV_16UC1);
  for (long y = 0; y < h; ++y)
    for (long x = 0; x < w; ++x) {
      const double v = data[static_cast<std::size_t>(y * w + x)];
      // FITS rows run bottom-up in most viewers but the array order is what the sensor wrote;
      // keep the array order (row 0 = first row stored).
      img.at<uint16_t>(static_cast<int>(y), static_cast<int>(x)) =
          std::isfinite(v) ? cv::saturate_cast<uint16_t>((v - offset) * scale) : 0;
    }
  out.image = img;
  return out;
}

}  // namespace

namespace {
/// OpenCV logs its own warning for a file it cannot decode; the InputError below says it in
/// the project's words. Whether OpenCV's line shows is the command line's policy (errors only
/// unless -v: app/cli/common_flags.cpp), not this function's.
cv::Mat readImage(const std::string& path) {
  cv::Mat raw;
  try {
    raw = cv::imread(path, cv::IMREAD_UNCHANGED);
  } catch (const cv::Exception&) {
    raw.release();
  }
  return raw;
}
}  // namespace

LoadedImage loadImage(const std::string& path) {
  if (isFitsPath(path)) return loadFits(path);
  cv::Mat raw = readImage(path);
  if (raw.empty()) {
    std::FILE* f = std::fopen(path.c_str(), "rb");
    if (!f) throw InputError(path + ": cannot open the image (no such file, or not readable)");
    std::fclose(f);
    throw InputError(path + ": cannot read image (PNG, JPEG, TIFF or FITS)");
  }
  cv::Mat grey;
  if (raw.channels() == 3)
    cv::cvtColor(raw, grey, cv::COLOR_BGR2GRAY);
  else if (raw.channels() == 4)
    cv::cvtColor(raw, grey, cv::COLOR_BGRA2GRAY);
  else
    grey = raw;
  LoadedImage out;
  if (grey.depth() == CV_8U || grey.depth() == CV_16U) {
    out.image = grey;
  } else {
    double lo = 0, hi = 0;
    cv::minMaxLoc(grey, &lo, &hi);
    grey.convertTo(out.image, CV_16U, hi > lo ? 65535.0 / (hi - lo) : 0.0,
                   hi > lo ? -lo * 65535.0 / (hi - lo) : 0.0);
  }
  const std::string name = path.substr(path.find_last_of('/') + 1);
  out.epoch_jyear = parseIsoEpoch(name);
  if (out.epoch_jyear) out.epoch_source = "file name";
  return out;
}

}  // namespace st::app

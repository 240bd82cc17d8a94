#include "common/output_file.hpp"
#include "imageio/image_file.hpp"

#include "imageio/fits.hpp"

#include "imageio/image_codecs.hpp"


#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <regex>
#include <utility>
#include <vector>

#include <opencv2/core/utils/logger.hpp>
#include <opencv2/imgproc.hpp>

#include "common/conventions.hpp"
#include "common/errors.hpp"
#include "common/log.hpp"

namespace st::imageio {

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

void requireImageSize(const std::string& path, std::int64_t w, std::int64_t h) {
  const std::string size = std::to_string(w) + "x" + std::to_string(h);
  if (w <= 0 || h <= 0) throw InputError(path + ": image of zero size (" + size + ")");
  if (w > kMaxImagePixels / h) {
    throw InputError(path + ": image too large (" + size + " pixels; at most " +
                     std::to_string(kMaxImagePixels) + " pixels are read)");
  }
  if (w < kMinImageSide || h < kMinImageSide) {
    throw InputError(path + ": image too small to hold star images (" + size +
                     " pixels; at least " + std::to_string(kMinImageSide) + " on each side)");
  }
}

bool isPngPath(const std::string& path) {
  const std::string p = lower(path);
  return p.size() > 4 && p.compare(p.size() - 4, 4, ".png") == 0;
}

bool isFitsPath(const std::string& path) {
  const std::string p = lower(path);
  for (const char* ext : {".fits", ".fit", ".fts", ".fits.gz", ".fit.gz", ".fts.gz"}) {
    const std::string e = ext;
    if (p.size() > e.size() && p.compare(p.size() - e.size(), e.size(), e) == 0) return true;
  }
  return false;
}

namespace {


/// Width and height from a PNG, PNM (P1..P6), TIFF (classic, first image) or JPEG header,
/// when the file is one; nothing decoded. Other formats: nullopt (OpenCV decodes them under
/// its own limit of 2^30 pixels, see readImage).
std::optional<std::pair<std::int64_t, std::int64_t>> headerSize(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) return std::nullopt;
  unsigned char b[24] = {0};
  f.read(reinterpret_cast<char*>(b), sizeof b);
  const std::streamsize n = f.gcount();
  const auto be = [](const unsigned char* p, int bytes) {
    std::int64_t v = 0;
    for (int i = 0; i < bytes; ++i) v = (v << 8) | p[i];
    return v;
  };
  static const unsigned char kPng[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (n >= 24 && std::equal(kPng, kPng + 8, b) && std::equal(b + 12, b + 16, "IHDR"))
    return std::make_pair(be(b + 16, 4), be(b + 20, 4));
  // Reads `bytes` bytes at `pos` (big- or little-endian); -1 when the file is shorter.
  const auto at = [&f](std::int64_t pos, int bytes, bool little) -> std::int64_t {
    unsigned char q[4] = {0};
    f.clear();
    f.seekg(pos);
    if (!f.read(reinterpret_cast<char*>(q), bytes)) return -1;
    std::int64_t v = 0;
    for (int i = 0; i < bytes; ++i) v = (v << 8) | q[little ? bytes - 1 - i : i];
    return v;
  };
  if (n >= 8 && ((b[0] == 'I' && b[1] == 'I') || (b[0] == 'M' && b[1] == 'M'))) {
    const bool le = b[0] == 'I';
    if (at(2, 2, le) != 42) return std::nullopt;  // BigTIFF or not a TIFF: OpenCV decides
    const std::int64_t ifd = at(4, 4, le), entries = at(ifd, 2, le);
    // Entries the file can hold: a damaged count must not cost 3 x 4096 failed seeks.
    f.clear();
    f.seekg(0, std::ios::end);
    const std::int64_t fits = (std::int64_t(f.tellg()) - ifd - 2) / 12;
    std::int64_t w = -1, h = -1;
    for (std::int64_t e = 0; e < std::min(entries, fits) && e < 4096; ++e) {
      const std::int64_t base = ifd + 2 + 12 * e;
      const std::int64_t tag = at(base, 2, le), type = at(base + 2, 2, le);
      if (tag != 256 && tag != 257) continue;
      const std::int64_t v = type == 3 ? at(base + 8, 2, le) : at(base + 8, 4, le);
      (tag == 256 ? w : h) = v;
    }
    if (w < 0 || h < 0) return std::nullopt;
    return std::make_pair(w, h);
  }
  if (n >= 4 && b[0] == 0xFF && b[1] == 0xD8) {
    // JPEG: segments after SOI up to a start-of-frame (SOF0..SOF15 but DHT, JPG, DAC).
    std::int64_t pos = 2;
    for (int seg = 0; seg < 1024; ++seg) {
      if (at(pos, 1, false) != 0xFF) return std::nullopt;
      const std::int64_t marker = at(pos + 1, 1, false);
      if (marker == 0xFF) {  // fill byte
        ++pos;
        continue;
      }
      const std::int64_t len = at(pos + 2, 2, false);
      if (len < 2) return std::nullopt;
      if (marker >= 0xC0 && marker <= 0xCF && marker != 0xC4 && marker != 0xC8 &&
          marker != 0xCC)
        return std::make_pair(at(pos + 7, 2, false), at(pos + 5, 2, false));
      pos += 2 + len;
    }
    return std::nullopt;
  }
  if (n >= 2 && b[0] == 'P' && b[1] >= '1' && b[1] <= '6') {
    // PNM: magic, then width and height as decimal tokens with '#' comments between.
    f.clear();
    f.seekg(2);
    std::int64_t v[2] = {-1, -1};
    for (int k = 0; k < 2; ++k) {
      int c = f.get();
      while (c != EOF && (std::isspace(c) || c == '#')) {
        if (c == '#')
          while (c != EOF && c != '\n') c = f.get();
        c = f.get();
      }
      if (c == EOF || !std::isdigit(c)) return std::nullopt;  // OpenCV reports it
      std::int64_t x = 0;
      for (; c != EOF && std::isdigit(c); c = f.get()) {
        x = x * 10 + (c - '0');
        if (x > (std::int64_t(1) << 40)) break;  // absurd already
      }
      v[k] = x;
    }
    return std::make_pair(v[0], v[1]);
  }
  return std::nullopt;
}

/// NaN and infinite pixels are background: they take the median of the finite ones. Returns
/// how many there were; throws when no pixel is finite.
std::size_t nonFiniteToBackground(const std::string& path, double* data, std::size_t n) {
  std::vector<double> finite;
  finite.reserve(n);
  for (std::size_t i = 0; i < n; ++i)
    if (std::isfinite(data[i])) finite.push_back(data[i]);
  if (finite.empty()) throw InputError(path + ": image has no finite pixels (all NaN or inf)");
  const std::size_t bad = n - finite.size();
  if (bad == 0) return 0;
  auto mid = finite.begin() + finite.size() / 2;
  std::nth_element(finite.begin(), mid, finite.end());
  for (std::size_t i = 0; i < n; ++i)
    if (!std::isfinite(data[i])) data[i] = *mid;
  log::info("%s: %zu NaN/inf pixels (of %zu) treated as background (median %g)", path.c_str(),
            bad, n, *mid);
  return bad;
}

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
  try {
    requireImageSize(path, w, h);  // before allocating the pixels
  } catch (const InputError&) {
    int s2 = 0;
    fits_close_file(f, &s2);
    throw;
  }
  if (naxis > 2) {
    long planes = 1;
    for (int k = 2; k < std::min(naxis, 3); ++k) planes *= naxes[k];
    if (planes > 1) log::info("%s: %d-D FITS image; its first plane is read", path.c_str(), naxis);
  }
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
  nonFiniteToBackground(path, data.data(), data.size());
  // Integer data within 0..65535 is kept as is; anything else is scaled onto 16 bits.
  double lo = 1e300, hi = -1e300;
  bool integral = true;
  for (double v : data) {
    lo = std::min(lo, v), hi = std::max(hi, v);
    integral = integral && v == std::floor(v);
  }
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
OtherFormats& otherFormatsHook() {
  static OtherFormats hook;
  return hook;
}

}  // namespace

cv::Mat readImagePixels(const std::string& path) {
  try {
    if (std::optional<cv::Mat> m = decode(path)) return std::move(*m);
  } catch (const std::bad_alloc&) {
    throw InputError(path + ": image too large to decode (out of memory)");
  }
  if (otherFormatsHook().read) return otherFormatsHook().read(path);
  throw InputError(path + ": not a PNG, JPEG, TIFF, PNM (P5/P6) or FITS image");
}

void setOtherFormats(OtherFormats formats) { otherFormatsHook() = std::move(formats); }

LoadedImage loadImage(const std::string& path) {
  if (isFitsPath(path)) return loadFits(path);
  {
    std::FILE* f = std::fopen(path.c_str(), "rb");
    if (!f) throw InputError(path + ": cannot open the image (no such file, or not readable)");
    const bool empty = std::fgetc(f) == EOF;
    std::fclose(f);
    if (empty) throw InputError(path + ": empty file (0 bytes), not an image");
  }
  if (const auto wh = headerSize(path)) requireImageSize(path, wh->first, wh->second);
  cv::Mat raw = readImagePixels(path);
  if (raw.empty()) throw InputError(path + ": cannot read image (PNG, JPEG, TIFF, PGM or FITS)");
  requireImageSize(path, raw.cols, raw.rows);
  cv::Mat grey;
  if (raw.channels() == 1) {
    grey = raw;
  } else if (raw.channels() == 3 || raw.channels() == 4) {
    cv::cvtColor(raw, grey, raw.channels() == 3 ? cv::COLOR_BGR2GRAY : cv::COLOR_BGRA2GRAY);
    log::info("%s: colour image (%d channels) converted to grey", path.c_str(), raw.channels());
  } else if (raw.channels() == 2) {
    cv::extractChannel(raw, grey, 0);
    log::info("%s: grey + alpha image; the alpha channel is dropped", path.c_str());
  } else {
    throw InputError(path + ": image with " + std::to_string(raw.channels()) +
                     " channels (grey or colour expected)");
  }
  LoadedImage out;
  if (grey.depth() == CV_8U || grey.depth() == CV_16U) {
    out.image = grey;
  } else {
    cv::Mat g64;
    grey.convertTo(g64, CV_64F);
    nonFiniteToBackground(path, g64.ptr<double>(), g64.total());
    double lo = 0, hi = 0;
    cv::minMaxLoc(g64, &lo, &hi);
    g64.convertTo(out.image, CV_16U, hi > lo ? 65535.0 / (hi - lo) : 0.0,
                  hi > lo ? -lo * 65535.0 / (hi - lo) : 0.0);
  }
  const std::string name = path.substr(path.find_last_of('/') + 1);
  out.epoch_jyear = parseIsoEpoch(name);
  if (out.epoch_jyear) out.epoch_source = "file name";
  return out;
}

std::optional<ImageProbe> probeImage(const std::string& path) {
  if (isFitsPath(path)) return std::nullopt;  // its epoch may be in DATE-OBS
  const auto wh = headerSize(path);
  if (!wh || wh->first < kMinImageSide || wh->second < kMinImageSide ||
      wh->first > kMaxImagePixels / wh->second)
    return std::nullopt;  // loadImage says why
  ImageProbe p;
  p.width = int(wh->first);
  p.height = int(wh->second);
  p.epoch_jyear = parseIsoEpoch(path.substr(path.find_last_of('/') + 1));
  if (p.epoch_jyear) p.epoch_source = "file name";
  return p;
}

void writeImage(const std::string& path, const cv::Mat& image) {
  const bool wide = image.type() == CV_16UC1;
  if (!wide && image.type() != CV_8UC1)
    throw InputError(path + ": only mono 8/16-bit images are written (got " +
                     cv::typeToString(image.type()) + ")");
  if (isPngPath(path)) return writePng(path, image);
  if (!isFitsPath(path)) {
    if (!otherFormatsHook().write)
      throw InputError(path + ": cannot write this image format here (try .fits or .png)");
    return otherFormatsHook().write(path, image);
  }
  fitsfile* f = nullptr;
  int status = 0;
  long naxes[2] = {image.cols, image.rows};
  PendingOutput out(path);  // under its real name only once complete
  const std::string clobber = "!" + out.tempPath();  // cfitsio's way of replacing a file
  fits_create_file(&f, clobber.c_str(), &status);
  fits_create_img(f, wide ? USHORT_IMG : BYTE_IMG, 2, naxes, &status);
  const cv::Mat c = image.isContinuous() ? image : image.clone();
  fits_write_img(f, wide ? TUSHORT : TBYTE, 1, static_cast<LONGLONG>(c.total()),
                 const_cast<uchar*>(c.data), &status);
  if (f) fits_close_file(f, &status);
  if (status) {
    char msg[FLEN_STATUS] = {0};
    fits_get_errstatus(status, msg);
    throw InputError(path + ": cannot write the FITS image (cfitsio: " + msg + ")");
  }
  out.commit();
}

}  // namespace st::imageio

/// @file image_io.hpp
/// Reading a sky image for `solve`: PNG, JPEG, TIFF, PGM (8/16-bit) through OpenCV, FITS
/// (primary image HDU) through cfitsio. Also the epoch of the image when it is known (FITS
/// DATE-OBS, or an ISO timestamp such as 2019-07-29T204726 in the file name).
///
/// What an image may be (anything else is an InputError naming the file -> exit 2, in the
/// project's words, never OpenCV's assertion text):
///  - size: at least kMinImageSide px on each side (a 1xN strip holds no star image) and at
///    most kMaxImagePixels pixels (100 Mpx: 200 MB at 16 bits before the detector's working
///    copies). The size is checked from the header before any pixel is decoded: PNG, PNM
///    (PGM/PPM), classic TIFF and JPEG headers are read here, FITS through cfitsio's header.
///    Any other format OpenCV reads (BMP, WebP, ...) is decoded under OpenCV's own limit
///    (OPENCV_IO_MAX_IMAGE_PIXELS, 2^30 by default; OpenCV 4.6 reads it when the library
///    loads, so it cannot be lowered from here) and then checked against ours.
///  - depth: 8 and 16 bits are kept as they are (a 16-bit PNG stays 16-bit); float (TIFF 32F,
///    FITS) is scaled onto 16 bits.
///  - channels: colour (3-channel BGR, 4-channel BGRA, grey+alpha) is converted to grey with
///    an info line saying so (star light is in every channel; alpha is dropped).
///  - NaN / infinite pixels (FITS, float TIFF: masked or dead pixels) are background: they
///    take the median of the finite pixels, with an info line counting them. An image with
///    no finite pixel is refused.
#pragma once
#include <cstdint>
#include <optional>
#include <string>

#include <opencv2/core.hpp>

namespace st::app {

/// Largest image loadImage() accepts, in pixels (width x height).
constexpr std::int64_t kMaxImagePixels = 100'000'000;
/// Smallest width and height loadImage() accepts, in pixels.
constexpr int kMinImageSide = 16;

struct LoadedImage {
  cv::Mat image;                      ///< CV_8UC1 or CV_16UC1
  std::optional<double> epoch_jyear;  ///< observation epoch when known
  std::string epoch_source;           ///< where the epoch came from ("DATE-OBS", "file name")
};

/// True for the FITS file names (.fits, .fit, .fts, also gzipped), any case.
bool isFitsPath(const std::string& path);

/// Throws InputError naming the file when it cannot be read or is outside the limits above.
LoadedImage loadImage(const std::string& path);

/// Writes a mono 8/16-bit image: FITS (BITPIX 8, or 16 with BZERO 32768 for unsigned) when
/// the name says FITS, else the format the extension names through OpenCV (PNG, TIFF, PGM keep
/// 16 bits). An existing file is replaced. Throws InputError naming the file.
void writeImage(const std::string& path, const cv::Mat& image);

/// Julian year of "YYYY-MM-DD[Thh[:]mm[:]ss[.s]]" (UTC); nullopt when it does not parse.
std::optional<double> parseIsoEpoch(const std::string& text);

}  // namespace st::app

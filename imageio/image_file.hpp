/// @file image_io.hpp
/// Reading a sky image for `solve`: PNG, JPEG, TIFF, PGM (8/16-bit) through libpng, libjpeg and
/// libtiff (image_codecs.hpp), FITS
/// (primary image HDU) through cfitsio. Also the epoch of the image when it is known (FITS
/// DATE-OBS, or an ISO timestamp such as 2019-07-29T204726 in the file name).
///
/// What an image may be (anything else is an InputError naming the file -> exit 2, in the
/// project's words, never OpenCV's assertion text):
///  - size: at least kMinImageSide px on each side (a 1xN strip holds no star image) and at
///    most kMaxImagePixels pixels (100 Mpx: 200 MB at 16 bits before the detector's working
///    copies). The size is checked from the header before any pixel is decoded: PNG, PNM
///    (PGM/PPM), classic TIFF and JPEG headers are read here, FITS through cfitsio's header.
///    Any other format OpenCV reads (BMP, WebP, ...), where a program registered OpenCV's
///    reader (setOtherFormats), is decoded under OpenCV's own limit
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
#include <functional>
#include <optional>
#include <string>

#include <opencv2/core.hpp>

namespace st::imageio {

/// Largest image loadImage() accepts, in pixels (width x height).
constexpr std::int64_t kMaxImagePixels = 100'000'000;
/// Smallest width and height loadImage() accepts, in pixels.
constexpr int kMinImageSide = 16;

struct LoadedImage {
  cv::Mat image;                      ///< CV_8UC1 or CV_16UC1
  std::optional<double> epoch_jyear;  ///< observation epoch when known
  std::string epoch_source;           ///< where the epoch came from ("DATE-OBS", "file name")
};

/// Refuses a width x height outside the limits above (InputError naming `path`).
void requireImageSize(const std::string& path, std::int64_t w, std::int64_t h);

/// What an image file says before it is decoded: its size from a PNG, JPEG, TIFF or PNM
/// header and its epoch from the file name (as loadImage gives them). nullopt for FITS (its
/// epoch may be DATE-OBS), other formats, and headers loadImage would refuse.
struct ImageProbe {
  int width = 0, height = 0;
  std::optional<double> epoch_jyear;
  std::string epoch_source;
};
std::optional<ImageProbe> probeImage(const std::string& path);

/// True for a file name ending in .png, any case.
bool isPngPath(const std::string& path);

/// True for the FITS file names (.fits, .fit, .fts, also gzipped), any case.
bool isFitsPath(const std::string& path);

/// Throws InputError naming the file when it cannot be read or is outside the limits above.
LoadedImage loadImage(const std::string& path);

/// The pixels of a PNG, JPEG, TIFF or PNM file as they are (what cv::imread(IMREAD_UNCHANGED)
/// gives: depth and channels kept; image_codecs.hpp), or of another format through the
/// registered OtherFormats. No size limits, no grey conversion: loadImage adds those.
/// Throws InputError naming the file.
cv::Mat readImagePixels(const std::string& path);

/// Writes a mono 8/16-bit image: FITS (BITPIX 8, or 16 with BZERO 32768 for unsigned) when
/// the name says FITS, PNG through libpng, else the format the extension names through the
/// registered OtherFormats (OpenCV: TIFF, PGM keep
/// 16 bits). An existing file is replaced. Throws InputError naming the file.
void writeImage(const std::string& path, const cv::Mat& image);

/// Formats beyond PNG, JPEG, TIFF, PNM and FITS (BMP, WebP, JPEG 2000, ...): OpenCV's
/// imgcodecs reads and writes them, but loading that library costs a program ~0.2 s at start
/// (GDAL, GDCM, poppler), so only the programs that want them register it
/// (imageio/opencv_formats.hpp). `read` returns what cv::imread(IMREAD_UNCHANGED) does and
/// throws InputError naming the file; `write` writes or throws InputError.
struct OtherFormats {
  std::function<cv::Mat(const std::string& path)> read;
  std::function<void(const std::string& path, const cv::Mat& image)> write;
};
void setOtherFormats(OtherFormats formats);

/// Julian year of "YYYY-MM-DD[Thh[:]mm[:]ss[.s]]" (UTC); nullopt when it does not parse.
std::optional<double> parseIsoEpoch(const std::string& text);

}  // namespace st::imageio

/// @file image_io.hpp
/// Reading a sky image for `solve`: PNG, JPEG, TIFF (8/16-bit; colour converted to grey)
/// through OpenCV, FITS (primary image HDU) through cfitsio. Also the epoch of the image
/// when it is known (FITS DATE-OBS, or an ISO timestamp such as 2019-07-29T204726 in the
/// file name).
#pragma once
#include <optional>
#include <string>

#include <opencv2/core.hpp>

namespace st::app {

struct LoadedImage {
  cv::Mat image;                      ///< CV_8UC1 or CV_16UC1
  std::optional<double> epoch_jyear;  ///< observation epoch when known
  std::string epoch_source;           ///< where the epoch came from ("DATE-OBS", "file name")
};

/// True for the FITS file names (.fits, .fit, .fts, also gzipped), any case.
bool isFitsPath(const std::string& path);

/// Throws InputError naming the file when it cannot be read.
LoadedImage loadImage(const std::string& path);

/// Julian year of "YYYY-MM-DD[Thh[:]mm[:]ss[.s]]" (UTC); nullopt when it does not parse.
std::optional<double> parseIsoEpoch(const std::string& text);

}  // namespace st::app

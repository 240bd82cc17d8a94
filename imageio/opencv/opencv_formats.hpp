/// @file opencv_formats.hpp
/// OpenCV's imgcodecs as the reader and writer of the formats image_codecs.hpp does not
/// decode (BMP, WebP, JPEG 2000, ...) and of TIFF/PGM output. A library of its own
/// (st_imageio_opencv) because imgcodecs costs ~0.2 s of dynamic loading at every start:
/// startracker-cli links it, startracker-solve does not.
#pragma once

namespace st::imageio {

/// Installs cv::imread / cv::imwrite as imageio's OtherFormats (image_file.hpp).
void registerOpenCvFormats();

}  // namespace st::imageio

/// @file image_codecs.hpp
/// Image file decoding and PNG encoding for the solve path without libopencv_imgcodecs: that
/// library drags ~140 shared libraries (GDAL, GDCM, poppler, HDF5) into the process and costs
/// ~210 ms of dynamic loading, four times the start-up budget of `startracker solve FRAME`.
/// The common sky-image formats go straight through libpng, libjpeg and libtiff instead, and
/// come back exactly as cv::imread(path, cv::IMREAD_UNCHANGED) would return them, so that
/// switching readers changes no result.
#pragma once
#include <opencv2/core.hpp>
#include <optional>
#include <string>

namespace st::imageio {

/// Which decoder a file's first bytes (magic number, not the extension) select.
enum class Format { kPng, kJpeg, kTiff, kPnm, kOther };

/// kPnm only for binary PGM/PPM (P5, P6); the ASCII and bitmap variants are kOther.
/// Throws st::InputError naming the file when it cannot be opened.
Format sniffFormat(const std::string& path);

/// Decodes PNG (libpng), JPEG (libjpeg), TIFF (libtiff), PGM/PPM binary P5/P6 (own reader)
/// into exactly what cv::imread(path, cv::IMREAD_UNCHANGED) returns for that file: same type
/// (CV_8U/CV_16U, 1/3/4 channels, colour as BGR/BGRA; CV_32FC1 for a float grey TIFF), same
/// pixels bit for bit. std::nullopt for Format::kOther (the caller then uses another reader).
/// A damaged or truncated file, or a TIFF layout this reader does not handle, is an
/// st::InputError naming the file and what is wrong -- never a crash, never a partial image.
/// Images over 2 GiB of pixel data are refused (the caller applies tighter limits later).
std::optional<cv::Mat> decode(const std::string& path);

/// Writes an 8- or 16-bit, 1-, 3- (BGR) or 4-channel (BGRA) image as PNG with libpng, with
/// cv::imwrite's settings (the same bytes), readable back bit-identical. Throws st::InputError
/// naming the file on failure, and then leaves no partial file behind.
void writePng(const std::string& path, const cv::Mat& image);

}  // namespace st::imageio

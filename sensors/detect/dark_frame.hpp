/// @file dark_frame.hpp
/// The master dark of seed 004 §4.1 ("the dark image was defined as the median of the
/// content of each pixel ... across several images in a sequence"): built from N dark
/// exposures, stored as a file, read back by `solve --dark` and the tracker key
/// `detect_dark_file`. The median, not the mean: a cosmic ray or a transient in one of the
/// frames leaves no trace as long as it hits fewer than half of them.
#pragma once
#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace st {

/// Per-pixel median of `frames` (all CV_8UC1 or all CV_16UC1, one size; checked by the
/// caller). For an even count the lower of the two middle values: integer, never a value
/// that no frame had. Empty input gives an empty Mat.
cv::Mat medianDark(const std::vector<cv::Mat>& frames);

/// What a dark looks like: mean and spread of its pixels and its hot pixels, those above
/// mean + k * sigma (sigma robust, IQR / 1.349 of the pixels read as whole numbers,
/// background.hpp's robustLevelSigma, so the hot pixels themselves do not inflate it).
struct DarkStats {
  double mean = 0, sigma = 0;
  long hot_pixels = 0;
};
DarkStats darkStats(const cv::Mat& dark, double k_sigma);

/// Reads a dark frame: FITS (BITPIX 8 or 16, as `startracker dark` writes it) or any mono
/// 8/16-bit image OpenCV reads (PNG, TIFF, PGM). Throws InputError naming the file.
cv::Mat readDarkFrame(const std::string& path);

}  // namespace st

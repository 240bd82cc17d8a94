/// @file frame_input.hpp
/// What `solve` identifies: the centroids of a frame, from an image (detected here) or from
/// a star list (given; detection skipped), with the image size and the epoch when known.
#pragma once
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "sensors/detect/centroid.hpp"
#include "sensors/detect/star_detector.hpp"

namespace st::solve {

struct SolveOptions;

struct FrameInput {
  cv::Mat image;  ///< empty for a star list
  bool star_list = false;
  int width = 0, height = 0;
  std::vector<Centroid> stars;  ///< brightest first
  std::string detection_reason;  ///< why detection found nothing usable ("" = fine)
  /// Detection's view of the frame (an image's; star lists have none): the PSF's three-pixel
  /// width along x and y it measured, the radiation hits it flagged, the blobs it dropped.
  double psf_width_x = 0, psf_width_y = 0;
  int hits = 0;
  double pixel_aspect = 1;  ///< the camera's fx / fy detection judged the blobs with
  std::vector<DetectionResult::Rejected> rejected;
  std::optional<double> epoch_jyear;
  std::string epoch_source;
  double load_ms = 0, detect_ms = 0;
};

/// Loads o.input; throws InputError naming the file (or --width/--height for a star list
/// without its image size).
/// `pixel_aspect`: the camera's fx / fy, for the blobs' shapes (DetectorOptions::pixel_aspect).
FrameInput loadFrameInput(const SolveOptions& o, double pixel_aspect = 1);
/// Detects the stars of an 8- or 16-bit grey image in memory (o.dark_frame subtracted; `name`
/// in messages). The result's image is a header on `image`, not a copy.
FrameInput frameInputFromImage(const cv::Mat& image, const SolveOptions& o, const std::string& name,
                               double pixel_aspect = 1);

}  // namespace st::solve

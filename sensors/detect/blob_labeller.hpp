/// @file blob_labeller.hpp
/// 8-connected blobs of the pixels above a threshold, found sparsely: each row is scanned
/// with a vector compare that skips background pixels 8-16 at a time, the pixels above the
/// threshold are kept as horizontal runs, and runs of consecutive rows that touch (8-connected)
/// are merged with a union-find over runs. The cost is one streaming compare of the frame plus
/// work proportional to the number of runs; no label image is written (a full-frame
/// connected-components pass costs many times more than the compare on a star field, where
/// well under 1% of the pixels are above the threshold).
///
/// Every blob is reported exactly once, with its area, bounding box, raw sum, first brightest
/// pixel (raster order) and its runs, which say exactly which pixels belong to it.
/// Buffers are kept between calls: a labeller reused frame after frame does not allocate.
#pragma once
#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

namespace st {

struct BlobRun {
  int y, x0, x1;  ///< row and first/last column (inclusive)
};

struct Blob {
  int area = 0;
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;  ///< bounding box, inclusive corners
  double sum_raw = 0;                  ///< sum of the raw pixel values [ADU]
  cv::Point peak;                      ///< first pixel (raster order) of the maximum
  double peak_raw = -1;                ///< its raw value [ADU]
  int first_run = 0, n_runs = 0;       ///< its runs: runs()[order()[first_run + k]]

  cv::Rect box() const { return {x0, y0, x1 - x0 + 1, y1 - y0 + 1}; }
};

class BlobLabeller {
 public:
  /// Blobs of the pixels of `grey` (CV_8UC1 / CV_16UC1) strictly above a threshold that is
  /// constant on square tiles of side `tile` (row-major `thresholds`, tiles_x per row; tile 0:
  /// one threshold for the frame, thresholds[0]).
  void labelThreshold(const cv::Mat& grey, int tile, int tiles_x,
                      const std::vector<double>& thresholds);
  /// Blobs of the non-zero pixels of `mask` (CV_8UC1, same size), values read from `grey`.
  void labelMask(const cv::Mat& mask, const cv::Mat& grey);

  const std::vector<Blob>& blobs() const { return blobs_; }  ///< in raster order of first pixel
  const std::vector<BlobRun>& runs() const { return runs_; }
  const std::vector<int>& order() const { return order_; }  ///< run indices grouped by blob

  /// Calls f(x, y, raw value) for each pixel of blob `b`, in raster order.
  template <typename F>
  void forEachPixel(const cv::Mat& grey, const Blob& b, F&& f) const {
    for (int k = 0; k < b.n_runs; ++k) {
      const BlobRun& r = runs_[static_cast<std::size_t>(order_[static_cast<std::size_t>(b.first_run + k)])];
      if (grey.depth() == CV_8U) {
        const uint8_t* row = grey.ptr<uint8_t>(r.y);
        for (int x = r.x0; x <= r.x1; ++x) f(x, r.y, static_cast<double>(row[x]));
      } else {
        const uint16_t* row = grey.ptr<uint16_t>(r.y);
        for (int x = r.x0; x <= r.x1; ++x) f(x, r.y, static_cast<double>(row[x]));
      }
    }
  }

 private:
  template <typename T, typename V>
  void scan(const cv::Mat& test, const cv::Mat& values, int tile, int tiles_x,
            const std::vector<double>& thresholds);
  void addRun(int y, int x0, int x1, double sum, double peak, int peak_x);
  void linkRows(std::size_t prev_begin, std::size_t prev_end, std::size_t cur_begin);
  int find(int i);
  void finish();

  std::vector<BlobRun> runs_;
  std::vector<double> run_sum_, run_peak_;
  std::vector<int> run_peak_x_, parent_, run_blob_, order_, counts_;
  std::vector<Blob> blobs_;
};

}  // namespace st

#include "sensors/detect/prefilter.hpp"

#include <opencv2/imgproc.hpp>

namespace st {
namespace {

// starCentroid2: count the candidates in the 5x5 box centred on each pixel (seed 004 §4.1:
// "at least 9 of the 25 pixels in this region also exceed the threshold").
void neighbourhood(cv::Mat& mask, int min_count) {
  cv::Mat ones, count, keep;
  cv::threshold(mask, ones, 0, 1, cv::THRESH_BINARY);
  cv::boxFilter(ones, count, CV_8U, cv::Size(5, 5), cv::Point(-1, -1), false,
                cv::BORDER_CONSTANT);
  cv::compare(count, min_count - 1, keep, cv::CMP_GT);
  cv::bitwise_and(mask, keep, mask);
}

// starCentroid3: the same count on fixed 5x5 cells (one count per 25 pixels). A star that
// straddles cells is kept through the neighbouring-cell rule.
void grid(cv::Mat& mask, int min_count) {
  const int cw = (mask.cols + 4) / 5, ch = (mask.rows + 4) / 5;
  cv::Mat1b pass(ch, cw, uchar(0));
  for (int r = 0; r < mask.rows; ++r) {
    const uchar* row = mask.ptr<uchar>(r);
    uchar* cells = pass[r / 5];
    for (int c = 0; c < mask.cols; ++c)
      if (row[c]) ++cells[c / 5];  // at most 25 per cell: fits in a byte
  }
  cv::Mat1b ok = pass >= min_count;
  cv::dilate(ok, ok, cv::Mat());  // 3x3: a passing cell keeps its 8 neighbours
  for (int r = 0; r < mask.rows; ++r) {
    uchar* row = mask.ptr<uchar>(r);
    const uchar* cells = ok[r / 5];
    for (int c = 0; c < mask.cols; ++c)
      if (!cells[c / 5]) row[c] = 0;
  }
}

}  // namespace

bool applyPrefilter(cv::Mat& mask, const std::string& name, int min_count) {
  if (name == "none") return true;
  if (name == "neighbourhood") {
    neighbourhood(mask, min_count);
    return true;
  }
  if (name == "grid") {
    grid(mask, min_count);
    return true;
  }
  return false;
}

std::vector<std::string> prefilterNames() { return {"none", "neighbourhood", "grid"}; }

}  // namespace st

#include "solve/annotate.hpp"

#include "imageio/image_codecs.hpp"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "common/errors.hpp"

namespace st::solve {

namespace {
/// Grey -> 8 bit with the 1st..99.9th percentile mapped to 0..255 (a sqrt stretch brings out
/// faint stars without saturating the bright ones).
cv::Mat stretch(const cv::Mat& grey) {
  cv::Mat f;
  grey.convertTo(f, CV_32F);
  std::vector<float> v;
  v.reserve(static_cast<std::size_t>(f.total() / 16 + 1));
  for (int r = 0; r < f.rows; r += 4)
    for (int c = 0; c < f.cols; c += 4) v.push_back(f.at<float>(r, c));
  auto pct = [&](double p) {
    auto it = v.begin() + static_cast<std::ptrdiff_t>(p * (v.size() - 1));
    std::nth_element(v.begin(), it, v.end());
    return *it;
  };
  const float lo = pct(0.01), hi = std::max(pct(0.999), lo + 1.0f);
  f = (f - lo) / (hi - lo);
  cv::max(f, 0.0, f);
  cv::min(f, 1.0, f);
  cv::sqrt(f, f);
  cv::Mat out8;
  f.convertTo(out8, CV_8U, 255.0);
  cv::Mat bgr;
  cv::cvtColor(out8, bgr, cv::COLOR_GRAY2BGR);
  return bgr;
}
}  // namespace

cv::Mat annotateFrame(const cv::Mat& grey, const std::vector<MarkedBlob>& blobs,
                      const std::vector<LabelledStar>& identified,
                      const std::vector<std::string>& caption, double pixel_aspect) {
  cv::Mat img = stretch(grey);
  // Binned rows: each repeated, so that the picture has the sky's proportions.
  const int rows = pixel_aspect >= 1.5 ? static_cast<int>(std::lround(pixel_aspect)) : 1;
  if (rows > 1) cv::resize(img, img, cv::Size(img.cols, img.rows * rows), 0, 0, cv::INTER_NEAREST);
  const double scale = std::max(0.4, img.cols / 1600.0);
  const int thick = std::max(1, static_cast<int>(scale * 1.5));
  auto pt = [rows](const Vec2& p) {
    return cv::Point(cvRound(p.x()), cvRound((p.y() + 0.5) * rows - 0.5));
  };
  const int r = static_cast<int>(8 * scale + 4);
  for (const MarkedBlob& b : blobs) {
    switch (b.kind) {
      case BlobKind::kStar:
        cv::circle(img, pt(b.px), r, cv::Scalar(0, 165, 255), 1, cv::LINE_AA);  // orange
        break;
      case BlobKind::kHit: {  // magenta cross: charge, not light
        const cv::Point c = pt(b.px), d(r / 2 + 2, r / 2 + 2), e(r / 2 + 2, -(r / 2 + 2));
        cv::line(img, c - d, c + d, cv::Scalar(255, 0, 255), 1, cv::LINE_AA);
        cv::line(img, c - e, c + e, cv::Scalar(255, 0, 255), 1, cv::LINE_AA);
        break;
      }
      case BlobKind::kDiffuse:
        cv::circle(img, pt(b.px), r, cv::Scalar(0, 255, 255), 1, cv::LINE_AA);  // yellow
        break;
      case BlobKind::kRejected:
        cv::circle(img, pt(b.px), r / 2, cv::Scalar(128, 128, 128), 1, cv::LINE_AA);  // grey
        break;
    }
  }
  for (const LabelledStar& s : identified) {
    cv::circle(img, pt(s.px), static_cast<int>(12 * scale + 6), cv::Scalar(80, 255, 80), thick,
               cv::LINE_AA);
    cv::putText(img, s.label, pt(s.px) + cv::Point(static_cast<int>(14 * scale + 6), -4),
                cv::FONT_HERSHEY_SIMPLEX, 0.45 * scale + 0.2, cv::Scalar(80, 255, 80), 1,
                cv::LINE_AA);
  }
  int y = static_cast<int>(22 * scale + 6);
  for (const std::string& line : caption) {
    cv::putText(img, line, cv::Point(8, y), cv::FONT_HERSHEY_SIMPLEX, 0.5 * scale + 0.2,
                cv::Scalar(255, 255, 255), 1, cv::LINE_AA);
    y += static_cast<int>(22 * scale + 6);
  }
  return img;
}

void writeAnnotatedFrame(const std::string& path, const cv::Mat& grey,
                         const std::vector<MarkedBlob>& blobs,
                         const std::vector<LabelledStar>& identified,
                         const std::vector<std::string>& caption, double pixel_aspect) {
  imageio::writePng(path, annotateFrame(grey, blobs, identified, caption, pixel_aspect));
}

}  // namespace st::solve

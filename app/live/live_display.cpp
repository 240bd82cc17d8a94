#include "app/live/live_display.hpp"

#include <cstdio>
#include <cstdlib>
#include <opencv2/highgui.hpp>
#include <opencv2/imgproc.hpp>

#include "common/conventions.hpp"
#include "sensors/detect/star_detector.hpp"

namespace st::app {

bool LiveDisplay::open(const std::string& title, std::string* why) {
  const char* x = std::getenv("DISPLAY");
  const char* w = std::getenv("WAYLAND_DISPLAY");
  if ((!x || !*x) && (!w || !*w)) {
    if (why) *why = "no display (DISPLAY and WAYLAND_DISPLAY are unset)";
    return false;
  }
  try {
    cv::namedWindow(title, cv::WINDOW_AUTOSIZE);
  } catch (const cv::Exception& e) {
    if (why) *why = e.what();
    return false;
  }
  title_ = title;
  open_ = true;
  return true;
}

cv::Mat LiveDisplay::render(const cv::Mat& frame, const CObservationStarTracker* fix,
                            const std::optional<Quat>& attitude) {
  cv::Mat grey8;
  if (frame.empty()) {
    grey8 = cv::Mat::zeros(480, 640, CV_8U);
  } else {
    // Stretch from the median-ish background to a few percent of the peak so faint stars show.
    double lo = 0, hi = 0;
    cv::minMaxLoc(frame, &lo, &hi);
    const double top = lo + 0.25 * (hi - lo) + 1.0;
    frame.convertTo(grey8, CV_8U, 255.0 / (top - lo), -lo * 255.0 / (top - lo));
  }
  cv::Mat out;
  cv::cvtColor(grey8, out, cv::COLOR_GRAY2BGR);
  if (!frame.empty()) {
    const DetectionResult det = detectStars(frame);
    for (const auto& c : det.stars)
      cv::circle(out, cv::Point2d(c.px.x(), c.px.y()), 4, cv::Scalar(0, 200, 255), 1,
                 cv::LINE_AA);
  }
  if (fix) {
    for (const auto& s : fix->stars) {
      const cv::Point2d p(s.px.x(), s.px.y());
      cv::circle(out, p, 9, cv::Scalar(0, 255, 0), 1, cv::LINE_AA);
      cv::putText(out, std::to_string(s.catalog_id), p + cv::Point2d(10, -6),
                  cv::FONT_HERSHEY_PLAIN, 0.9, cv::Scalar(0, 255, 0), 1, cv::LINE_AA);
    }
  }
  char text[200];
  std::optional<Quat> q = attitude;
  const char* what = "filter";
  if (!q && fix && fix->hasAttitude()) {
    q = fix->q_ib;
    what = "fix";
  }
  if (q) {
    const RaDecRoll r = raDecRollFromAttitude(*q);
    std::snprintf(text, sizeof(text), "%s: RA %.4f  Dec %+.4f  roll %+.3f deg", what,
                  rad2deg(r.ra), rad2deg(r.dec), rad2deg(r.roll));
  } else {
    std::snprintf(text, sizeof(text), "no attitude yet");
  }
  cv::putText(out, text, cv::Point(8, 18), cv::FONT_HERSHEY_PLAIN, 1.1, cv::Scalar(255, 255, 0),
              1, cv::LINE_AA);
  if (fix) {
    std::snprintf(text, sizeof(text), "%s, %zu stars, %d blobs%s%s", toString(fix->mode),
                  fix->stars.size(), fix->num_blobs, fix->reason.empty() ? "" : ": ",
                  fix->reason.c_str());
    cv::putText(out, text, cv::Point(8, 36), cv::FONT_HERSHEY_PLAIN, 1.0,
                cv::Scalar(255, 255, 0), 1, cv::LINE_AA);
  }
  return out;
}

void LiveDisplay::show(const cv::Mat& frame, const CObservationStarTracker* fix,
                       const std::optional<Quat>& attitude) {
  if (!open_) return;
  cv::imshow(title_, render(frame, fix, attitude));
}

bool LiveDisplay::quitRequested() {
  if (!open_) return false;
  const int key = cv::waitKey(1);
  return key == 'q' || key == 27;
}

void LiveDisplay::close() {
  if (!open_) return;
  cv::destroyWindow(title_);
  open_ = false;
}

}  // namespace st::app

#include "sensors/testbed/display_image.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>

namespace st::testbed {

std::vector<DisplayStar> skyOnDisplay(const DisplayGeometry& g, const std::vector<Vec3>& u_sky,
                                      const std::vector<double>& mag,
                                      const std::vector<uint32_t>& id, const Quat& q_sky_I,
                                      std::size_t max_stars) {
  std::vector<DisplayStar> out;
  const Quat q_I_sky = q_sky_I.conjugate();
  for (std::size_t k = 0; k < u_sky.size(); ++k) {
    const Vec3 v = q_I_sky * u_sky[k];
    if (!(v.z() > 1e-6)) continue;  // below the screen's plane
    const Vec3 S = v * (g.screen_distance_m / v.z());  // beta v (eq. 57)
    const Vec2 px = g.screenPixel(S);
    if (!g.isOnScreen(px)) continue;
    out.push_back({id[k], px, mag[k], u_sky[k]});
  }
  std::stable_sort(out.begin(), out.end(),
                   [](const DisplayStar& a, const DisplayStar& b) { return a.mag < b.mag; });
  if (out.size() > max_stars) out.resize(max_stars);
  return out;
}

cv::Mat drawDisplay(const DisplayGeometry& g, const std::vector<DisplayStar>& stars,
                    const DrawOptions& o) {
  cv::Mat img(g.screen_height_px, g.screen_width_px, CV_32F, cv::Scalar(0));
  if (!stars.empty()) {
    const double m0 = std::min_element(stars.begin(), stars.end(), [](auto& a, auto& b) {
                        return a.mag < b.mag;
                      })->mag;
    const int r = static_cast<int>(std::ceil(4 * o.dot_sigma_px));
    for (const DisplayStar& s : stars) {
      const double peak = std::max(o.min_peak, 255.0 * std::pow(10.0, -0.4 * (s.mag - m0)));
      const int cx = static_cast<int>(std::lround(s.screen_px.x()));
      const int cy = static_cast<int>(std::lround(s.screen_px.y()));
      for (int y = std::max(0, cy - r); y <= std::min(img.rows - 1, cy + r); ++y)
        for (int x = std::max(0, cx - r); x <= std::min(img.cols - 1, cx + r); ++x) {
          const double d2 = std::pow(x - s.screen_px.x(), 2) + std::pow(y - s.screen_px.y(), 2);
          img.at<float>(y, x) += static_cast<float>(peak * std::exp(-0.5 * d2 / (o.dot_sigma_px * o.dot_sigma_px)));
        }
    }
  }
  cv::Mat out;
  img.convertTo(out, CV_8U);  // saturates at 255
  return out;
}

cv::Mat photographDisplay(const cv::Mat& screen, const DisplayGeometry& g, const CameraModel& cam,
                          const Quat& q_ib, double noise_adu, uint64_t seed, double background,
                          double gain) {
  cv::Mat grey;
  if (screen.channels() == 3) {
    cv::Mat tmp;
    screen.convertTo(tmp, CV_8U);
    grey = cv::Mat(tmp.rows, tmp.cols, CV_8U);
    for (int y = 0; y < tmp.rows; ++y)
      for (int x = 0; x < tmp.cols; ++x) {
        const auto p = tmp.at<cv::Vec3b>(y, x);
        grey.at<uint8_t>(y, x) = static_cast<uint8_t>((p[0] + p[1] + p[2]) / 3);
      }
  } else {
    screen.convertTo(grey, CV_8U);
  }
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> n01;
  cv::Mat out(cam.height(), cam.width(), CV_8U);
  for (int y = 0; y < cam.height(); ++y)
    for (int x = 0; x < cam.width(); ++x) {
      double v = background;
      if (const auto S = g.screenPointFromCamera(cam.pixelToVector(Vec2(x, y)), q_ib)) {
        const Vec2 p = g.screenPixel(*S);
        const int x0 = static_cast<int>(std::floor(p.x())), y0 = static_cast<int>(std::floor(p.y()));
        if (x0 >= 0 && y0 >= 0 && x0 + 1 < grey.cols && y0 + 1 < grey.rows) {
          const double fx = p.x() - x0, fy = p.y() - y0;
          const double s = (1 - fx) * (1 - fy) * grey.at<uint8_t>(y0, x0) +
                           fx * (1 - fy) * grey.at<uint8_t>(y0, x0 + 1) +
                           (1 - fx) * fy * grey.at<uint8_t>(y0 + 1, x0) +
                           fx * fy * grey.at<uint8_t>(y0 + 1, x0 + 1);
          v += gain * s;
        }
      }
      v += noise_adu * n01(rng);
      out.at<uint8_t>(y, x) = static_cast<uint8_t>(std::clamp(std::lround(v), 0L, 255L));
    }
  return out;
}

}  // namespace st::testbed

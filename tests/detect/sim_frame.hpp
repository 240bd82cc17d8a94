/// @file sim_frame.hpp
/// Test helper: a 16-bit frame of Gaussian stars with background, Poisson shot noise,
/// Gaussian read noise and quantisation, and the Cramer-Rao bound of a star's position.
#pragma once
#include <random>
#include <vector>

#include <opencv2/core.hpp>

#include "common/attitude.hpp"
#include "sensors/detect/detector_options.hpp"
#include "sensors/sim/psf.hpp"

namespace st::test {

struct SimCamera {
  double background_e = 100;  ///< sky + dark per pixel [e-]
  double read_e = 5;          ///< read noise [e-]
  double gain = 2;            ///< [e-/ADU]
  double bias_adu = 100;      ///< offset [ADU]
  double psf_sigma = 1.0;     ///< [px]
};

struct SimStar {
  Vec2 px;
  double flux_e;
};

/// Detector options with the camera's noise model (gain, read noise in ADU).
inline DetectorOptions detectorOptionsFor(const SimCamera& cam) {
  DetectorOptions o;
  o.gain_e_per_adu = cam.gain;
  o.read_noise_adu = cam.read_e / cam.gain;
  return o;
}

/// Electrons image -> noisy 16-bit ADU frame.
inline cv::Mat noisyFrame(const cv::Mat& electrons, const SimCamera& cam, std::mt19937_64& rng) {
  cv::Mat out(electrons.size(), CV_16U);
  std::normal_distribution<double> read(0.0, cam.read_e);
  for (int r = 0; r < electrons.rows; ++r)
    for (int c = 0; c < electrons.cols; ++c) {
      const double mean = electrons.at<double>(r, c) + cam.background_e;
      std::poisson_distribution<long> shot(mean);
      const double e = static_cast<double>(shot(rng)) + read(rng);
      const double adu = std::round(e / cam.gain + cam.bias_adu);
      out.at<uint16_t>(r, c) = static_cast<uint16_t>(std::clamp(adu, 0.0, 65535.0));
    }
  return out;
}

inline cv::Mat renderFrame(int w, int h, const std::vector<SimStar>& stars, const SimCamera& cam,
                           std::mt19937_64& rng) {
  cv::Mat e = cv::Mat::zeros(h, w, CV_64F);
  for (const SimStar& s : stars) addGaussianStar(e, s.px, s.flux_e, cam.psf_sigma);
  return noisyFrame(e, cam, rng);
}

/// Fisher information of (x, y) [and of (x, y, F, B, s) when `full`] for one star: pixel
/// mean mu = B + F f_ij, variance mu + read^2 (Poisson + Gaussian read noise), in electrons.
/// Returns the CRB covariance of (x, y).
inline Mat2 cramerRaoXY(const Vec2& px, double flux_e, const SimCamera& cam, bool full) {
  using Vec5 = Eigen::Matrix<double, 5, 1>;
  Eigen::Matrix<double, 5, 5> I = Eigen::Matrix<double, 5, 5>::Zero();
  const int x0 = static_cast<int>(std::floor(px.x())) - 8, y0 = static_cast<int>(std::floor(px.y())) - 8;
  const double s = cam.psf_sigma, hds = 1e-5;
  auto f = [&](double a, double c, double sg) { return pixelFraction1d(a, c, sg); };
  for (int j = y0; j <= y0 + 17; ++j)
    for (int i = x0; i <= x0 + 17; ++i) {
      const double fx = f(i, px.x(), s), fy = f(j, px.y(), s);
      const double mu = cam.background_e + flux_e * fx * fy;
      const double var = mu + cam.read_e * cam.read_e;
      Vec5 d;
      d[0] = flux_e * fy * (f(i, px.x() + hds, s) - f(i, px.x() - hds, s)) / (2 * hds);
      d[1] = flux_e * fx * (f(j, px.y() + hds, s) - f(j, px.y() - hds, s)) / (2 * hds);
      d[2] = fx * fy;
      d[3] = 1.0;
      d[4] = flux_e * (f(i, px.x(), s + hds) * f(j, px.y(), s + hds) -
                       f(i, px.x(), s - hds) * f(j, px.y(), s - hds)) / (2 * hds);
      I += d * d.transpose() / var;
    }
  if (!full) return I.topLeftCorner<2, 2>().inverse();
  return I.inverse().topLeftCorner<2, 2>();
}

}  // namespace st::test

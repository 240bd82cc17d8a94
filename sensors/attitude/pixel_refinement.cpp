#include "sensors/attitude/pixel_refinement.hpp"

#include <Eigen/Cholesky>
#include <Eigen/LU>

#include "sensors/camera/jacobians.hpp"

namespace st {

PixelRefinement refineInPixels(const CameraModel& camera, const std::vector<PixelObservation>& obs,
                               const Quat& q_ic, double floor_px, std::vector<double>& e2) {
  PixelRefinement res;
  res.q_ic = q_ic;
  e2.resize(obs.size());
  const Mat2 floor2 = floor_px * floor_px * Mat2::Identity();
  constexpr int kSteps = 2;
  for (int it = 0; it <= kSteps; ++it) {
    const Mat3 R = res.q_ic.toRotationMatrix();
    Mat3 N = Mat3::Zero();
    Vec3 g = Vec3::Zero();
    res.chi2 = 0;
    for (std::size_t k = 0; k < obs.size(); ++k) {
      const Vec3 v = R.transpose() * obs[k].r_i;
      const auto px = camera.vectorToPixel(v);
      if (!px) {
        res.reason = "a matched star projects outside the camera";
        return res;
      }
      const Mat23 H = attitudeJacobian(camera, v);
      const Mat2 Ci = (obs[k].cov_px + floor2).inverse();
      const Vec2 d = obs[k].px - *px;
      N += H.transpose() * Ci * H;
      g += H.transpose() * Ci * d;
      e2[k] = d.dot(Ci * d);
      res.chi2 += e2[k];
    }
    if (it == kSteps) break;  // the last pass only evaluates the residuals
    // Seed 004 eq. 6.13 (step) and 6.15 (covariance), in pixels.
    const Eigen::LDLT<Mat3> ldlt(N);
    if (ldlt.info() != Eigen::Success || !(N.determinant() > 0)) {
      res.reason = "degenerate star geometry";
      return res;
    }
    res.q_ic = canonical(res.q_ic * quatExp(ldlt.solve(g)));
    res.cov_cam = N.inverse();
  }
  res.ok = true;
  return res;
}

}  // namespace st

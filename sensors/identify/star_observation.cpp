#include "sensors/identify/star_observation.hpp"

#include <algorithm>
#include <cmath>

namespace st {

std::vector<StarObservation> toStarObservations(const std::vector<Centroid>& centroids,
                                                const CameraModel& camera, double min_sigma_px,
                                                double model_error_px) {
  std::vector<StarObservation> out;
  out.reserve(centroids.size());
  const double min_sigma = min_sigma_px * camera.pixelScale();
  const double model_var = std::pow(model_error_px * camera.pixelScale(), 2);
  for (const Centroid& c : centroids) {
    StarObservation o;
    o.px = c.px;
    o.brightness = c.flux;
    o.v_cam = camera.pixelToVector(c.px);
    // d(normalised xy)/d(px) = J^-1; d(unit)/d(xy) = (I - u u^T) / |p| * [e_x e_y], p = v/v_z.
    const Mat2 j_inv = camera.pixelJacobian(o.v_cam).inverse();
    const Mat2 cov_xy = j_inv * c.cov_px * j_inv.transpose();
    const Vec3 p = o.v_cam / o.v_cam.z();
    Eigen::Matrix<double, 3, 2> d = (Mat3::Identity() - o.v_cam * o.v_cam.transpose())
                                        .leftCols<2>() / p.norm();
    const Mat3 cov_u = d * cov_xy * d.transpose();
    const double sigma = std::sqrt(std::max(0.0, cov_u.trace() / 2.0) + model_var);
    o.sigma = std::isfinite(sigma) ? std::max(sigma, min_sigma) : min_sigma;
    out.push_back(o);
  }
  return out;
}

}  // namespace st

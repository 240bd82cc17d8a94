#include "sensors/tracking/frame_rate.hpp"

#include <Eigen/LU>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <unordered_map>

namespace st {

RateFrame RateFrame::of(double t_s, const std::vector<MatchedStar>& stars, const Mat3& cov_cam) {
  RateFrame f;
  f.t_s = t_s;
  f.ids.reserve(stars.size());
  f.v_cam.reserve(stars.size());
  for (const MatchedStar& m : stars) {
    f.ids.push_back(m.catalog_id);
    f.v_cam.push_back(m.v_cam.normalized());
  }
  const double n = static_cast<double>(stars.size());
  const Eigen::FullPivLU<Mat3> lu(cov_cam);
  if (n > 0 && lu.isInvertible()) {
    const double info_trace = lu.inverse().trace();
    if (info_trace > 0) f.sigma = std::sqrt(2.0 * n / info_trace);
  }
  // The fix's own residuals (2 dof per star, 3 taken by the attitude) measure the per-star
  // scatter the centroid covariances may miss (streaks along the motion, the camera model):
  // the larger of the two is used.
  if (stars.size() >= 2) {
    double r2 = 0;
    for (const MatchedStar& m : stars) r2 += m.residual * m.residual;
    f.sigma = std::max(f.sigma, std::sqrt(r2 / (2.0 * n - 3.0)));
  }
  return f;
}

std::optional<MeasuredRate> measureFrameRate(const RateFrame& prev, const RateFrame& cur,
                                             const Mat3& R_body_cam) {
  const double dt = cur.t_s - prev.t_s;
  if (!(dt > 0) || !(prev.sigma > 0) || !(cur.sigma > 0)) return std::nullopt;
  std::unordered_map<uint32_t, std::size_t> in_prev;
  for (std::size_t k = 0; k < prev.ids.size(); ++k) in_prev.emplace(prev.ids[k], k);
  const double var = prev.sigma * prev.sigma + cur.sigma * cur.sigma;
  Mat3 B = Mat3::Zero(), info = Mat3::Zero();
  int n = 0;
  for (std::size_t k = 0; k < cur.ids.size(); ++k) {
    const auto it = in_prev.find(cur.ids[k]);
    if (it == in_prev.end()) continue;
    const Vec3& v1 = prev.v_cam[it->second];
    const Vec3& v2 = cur.v_cam[k];
    B += v1 * v2.transpose() / var;
    info += (Mat3::Identity() - v2 * v2.transpose()) / var;
    ++n;
  }
  if (n < 2) return std::nullopt;
  // Wahba by SVD: A_12 = U diag(1, 1, det U det V) V^T maximises tr(A^T B).
  const Eigen::JacobiSVD<Mat3> svd(B, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Mat3 D = Mat3::Identity();
  D(2, 2) = svd.matrixU().determinant() * svd.matrixV().determinant();
  const Mat3 A12 = svd.matrixU() * D * svd.matrixV().transpose();
  const Eigen::FullPivLU<Mat3> lu(info);
  if (!lu.isInvertible() || svd.singularValues()(1) <= 1e-12 * svd.singularValues()(0))
    return std::nullopt;
  const Vec3 phi = quatLog(canonical(Quat(A12)));
  MeasuredRate r;
  r.rate_body = R_body_cam * phi / dt;
  r.cov_body = R_body_cam * (lu.inverse() / (dt * dt)) * R_body_cam.transpose();
  r.cov_body = 0.5 * (r.cov_body + r.cov_body.transpose());
  r.interval_s = dt;
  r.stars = n;
  return r;
}

}  // namespace st

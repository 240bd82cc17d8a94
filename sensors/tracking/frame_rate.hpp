/// @file frame_rate.hpp
/// The body rate from two solved frames: the relative attitude of the frames from the stars
/// identified in both (the same catalog id), divided by the frame interval. Seed 004 ch. 7,
/// eq. 7.1: the relative attitude A_12 between two frames maps one frame's star vectors onto
/// the other's, v_1 = A_12 v_2, found here as a Wahba problem (SVD, Markley 1988) over the
/// common stars with no catalog direction involved; the mean rate over the interval is
/// w = Log(A_12) / dt (A_12 = Exp(w dt) for a constant rate).
///
/// Covariance: each pair's residual v_1 - A v_2 carries both frames' noise, sigma_k^2 =
/// sigma_1^2 + sigma_2^2 (the two images are independent), so the QUEST covariance of the
/// relative rotation (seed 004 §6) is (sum_k (I - v_k v_k^T) / sigma_k^2)^-1 and the rate's
/// is that divided by dt^2. Each frame's per-star sigma is the larger of the one its fix
/// covariance implies (n stars of equal sigma give a QUEST information of trace 2 n /
/// sigma^2) and its residuals' scatter, sum r_k^2 / (2 n - 3): on simulated slews the
/// centroid covariances alone made the rate's roll sigma 5x too small (streak errors along
/// the motion; tests/tracking/test_frame_rate.cpp).
///
/// The rate and the two fixes are NOT independent (the same star vectors): see
/// fusion/gyroless_model.hpp for why the fusion loop does not feed it to the filter.
#pragma once
#include <cstdint>
#include <optional>
#include <vector>

#include "common/attitude.hpp"
#include "sensors/tracking/frame.hpp"

namespace st {

/// One solved frame's stars, camera frame.
struct RateFrame {
  double t_s = 0;
  std::vector<uint32_t> ids;
  std::vector<Vec3> v_cam;
  double sigma = 0;  ///< [rad] per-star 1-sigma across the line of sight
  /// From a fix: its stars and the per-star sigma (its covariance's or its residuals').
  static RateFrame of(double t_s, const std::vector<MatchedStar>& stars, const Mat3& cov_cam);
};

/// The mean body rate from `prev` to `cur` (R_body_cam: body from camera); nothing when they
/// share fewer than 2 stars, the interval is not positive, or the geometry is degenerate.
std::optional<MeasuredRate> measureFrameRate(const RateFrame& prev, const RateFrame& cur,
                                             const Mat3& R_body_cam);

}  // namespace st

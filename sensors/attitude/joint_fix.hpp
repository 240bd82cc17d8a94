/// @file joint_fix.hpp
/// One attitude from several camera heads seen at the same time (issue 16: roll about one
/// boresight is several times worse than the cross-boresight axes; a second head at an angle
/// sees that roll as its own cross-boresight pointing).
///
/// Each head's fix is already the maximum-likelihood attitude of its own stars (a Wahba
/// solve refined in pixel space with each centroid's covariance, pixel_refinement.hpp) and
/// its covariance is the inverse of that head's Fisher information. Around its own optimum
/// the head's loss is 1/2 e^T P_h^-1 e + const, e = Log(R_h^T R) (seed 004 eqs. 6.13-6.17:
/// Gauss-Newton on the loss, covariance the inverse Hessian), so the loss of all heads' stars
/// together is the sum of those quadratics: its minimum is the joint Wahba solution over every
/// head's body-frame vectors, to second order in the heads' disagreement, with the
/// information of every centroid kept (an isotropic-sigma Wahba over the merged vectors would
/// drop the streaks' anisotropy). Gauss-Newton on
///   J(q) = sum_h Log(q_h^-1 q)^T P_h^-1 Log(q_h^-1 q),  covariance (sum_h P_h^-1)^-1,
/// and J at the minimum is ~ chi2(3 (n - 1)): heads that disagree beyond it are not one
/// attitude (a misidentified head, a mounting gone wrong) and the caller must not merge them.
///
/// Frames: every fix and the result are body-frame attitudes q_ib with body-frame
/// covariances (each head's tracker already applied its mounting, FrameResult).
#pragma once
#include <string>
#include <vector>

#include "common/attitude.hpp"

namespace st {

/// One head's fix in the body frame.
struct HeadFix {
  Quat q_ib = Quat::Identity();
  Mat3 cov_body = Mat3::Zero();  ///< [rad^2]
};

struct JointFix {
  bool ok = false;
  std::string reason;            ///< why not ok
  Quat q_ib = Quat::Identity();  ///< canonical
  Mat3 cov_body = Mat3::Zero();  ///< [rad^2] (sum_h P_h^-1)^-1
  double chi2 = 0;               ///< the heads' disagreement J at the result, ~ chi2(dof)
  int dof = 0;                   ///< 3 (heads - 1)
};

/// The joint attitude of >= 1 head fixes (one fix is returned as it is). Fails (ok false)
/// for no fix or a covariance that is not positive definite.
JointFix jointFix(const std::vector<HeadFix>& heads);

}  // namespace st

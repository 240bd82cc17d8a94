/// @file gyroless_model.hpp
/// The process model of the gyroless mode of AttitudeMekf (MekfOptions::Model::kGyroless):
/// no gyro, the body angular velocity is part of the state (issue 16 item 1).
///
/// State: global q_ib and the body rate w [rad/s]. Error state x = [dtheta; dw] (6), attitude
/// error in the BODY frame as for the gyro model: q_true = q_est (x) Exp(dtheta),
/// dw = w_true - w_est.
/// Dynamics: constant rate driven by a rate random walk,
///   q_dot = 1/2 q (x) [0; w],   w_dot = eta_w,   E[eta_w eta_w^T] = sw^2 I delta(t - t'),
/// sw = MekfOptions::rate_walk_rad_s2_rt_hz [rad/s^2/sqrt(Hz)] (an angular acceleration
/// spectral density: over a time T the rate wanders by sw sqrt(T) per axis).
/// Linearising q_true_dot about the estimate (as M&C eq. 6.3 for the gyro model, whose
/// w_true - w_est = -db - eta_v here becomes +dw):
///   dtheta_dot = -[w x] dtheta + dw,   dw_dot = eta_w.
/// Closed form over dt at the constant estimated rate w:
///   q <- q (x) Exp(w dt)                          (exact for a constant rate)
///   w <- w
///   Phi = [Theta  Psi_g; 0  I],  Theta = exp(-[w x] dt) = R(Exp(w dt))^T,
///         Psi_g = int_0^dt exp(-[w x] s) ds
///               = I dt - [w x] (1 - cos a)/|w|^2 + [w x]^2 (a - sin a)/|w|^3,  a = |w| dt
///         (the gyro model's Psi of M&C eq. 6.83 with the opposite sign: the rate error enters
///         with + instead of -);
///   Q = int_0^dt Phi(s) G sw^2 G^T Phi(s)^T ds, G = [0; I]
///     = sw^2 [dt^3/3 I, dt^2/2 I; dt^2/2 I, dt I]  to first order in |w| dt (as M&C eq. 6.93
///       neglects the rotation inside the integral: at 1 deg/s over 0.1 s, |w| dt = 0.0017).
/// There is no white attitude noise (no ARW: nothing is integrated but the state itself).
///
/// Updates are those of the gyro model (H = [I 0] for a fix, star vectors) plus a rate
/// measurement: y = w_meas - w, H = [0 I], 3x3 covariance R_w (e.g. a rate from two frames,
/// sensors/tracking/frame_rate.hpp). The reset w <- w + dw_hat is the gyro model's b <- b + db.
///
/// Why the loop (fusion_loop.hpp) does not feed the tracker's own frame-to-frame rate: it is
/// the relative rotation of the SAME two frames whose fixes the filter already takes, so its
/// error is a linear function of those fixes' errors (cov(w_meas, fix_k) != 0). Fed as an
/// independent measurement it would count each frame's information twice and make the rate
/// covariance overconfident. The rate update is for independent rate sources.
#pragma once
#include <Eigen/Core>

#include "common/attitude.hpp"

namespace st {

using Mat6g = Eigen::Matrix<double, 6, 6>;

/// Phi of the gyroless model over dt at rate w (see the file comment).
Mat6g gyrolessTransition(const Vec3& w, double dt);
/// Q of the gyroless model over dt for the rate walk density sw [rad/s^2/sqrt(Hz)].
Mat6g gyrolessProcessNoise(double sw, double dt);

}  // namespace st

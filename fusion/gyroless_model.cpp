#include "fusion/gyroless_model.hpp"

#include <cmath>

namespace st {

Mat6g gyrolessTransition(const Vec3& w, double dt) {
  const double n = w.norm();
  const double a = n * dt;
  const Mat3 W = skew(w);
  const Mat3 W2 = W * W;
  Mat3 Psi;
  if (a < 1e-4) {  // series for small angles (relative error < 1e-17)
    Psi = Mat3::Identity() * dt - W * (0.5 * dt * dt) + W2 * (dt * dt * dt / 6.0);
  } else {
    Psi = Mat3::Identity() * dt - W * ((1.0 - std::cos(a)) / (n * n)) +
          W2 * ((a - std::sin(a)) / (n * n * n));
  }
  Mat6g Phi = Mat6g::Identity();
  Phi.topLeftCorner<3, 3>() = quatExp(w * dt).toRotationMatrix().transpose();
  Phi.topRightCorner<3, 3>() = Psi;
  return Phi;
}

Mat6g gyrolessProcessNoise(double sw, double dt) {
  const double s2 = sw * sw;
  const double adt = std::abs(dt);  // backwards prediction: noise of |dt|, conservative
  Mat6g Q = Mat6g::Zero();
  Q.topLeftCorner<3, 3>().diagonal().setConstant(s2 * adt * adt * adt / 3.0);
  Q.topRightCorner<3, 3>().diagonal().setConstant(0.5 * s2 * dt * adt);
  Q.bottomLeftCorner<3, 3>().diagonal().setConstant(0.5 * s2 * dt * adt);
  Q.bottomRightCorner<3, 3>().diagonal().setConstant(s2 * adt);
  return Q;
}

}  // namespace st

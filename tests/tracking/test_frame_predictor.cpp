// The tracker's frame-to-frame predictor without images: the rate match (seed 004 §5.5.3)
// carries a constant rate exactly, a measured rate wins over it, an external prediction over
// both, stale fixes predict nothing; the acceleration correction moves a fix by a T^2 / 24.
#include <gtest/gtest.h>

#include "common/conventions.hpp"
#include "sensors/tracking/frame_predictor.hpp"

namespace st {
namespace {

CameraFix fixAt(double t, const Vec3& rate, const Quat& q0) {
  return {t, canonical(q0 * quatExp(rate * t)), 1e-10 * Mat3::Identity()};
}

TEST(FramePredictor, RateMatchCarriesAConstantRateAndAMeasuredRateWins) {
  const Quat q0 = attitudeFromRaDecRoll({deg2rad(10.0), deg2rad(20.0), deg2rad(30.0)});
  const Vec3 w(deg2rad(0.8), deg2rad(-0.5), deg2rad(0.3));
  FramePredictor p(FramePredictorOptions{});
  PredictionSource src;
  EXPECT_FALSE(p.predict(0.1, std::nullopt, std::nullopt, &src));  // nothing yet
  p.addLostInSpaceFix(fixAt(0.0, w, q0));
  EXPECT_FALSE(p.predict(0.1, std::nullopt, std::nullopt, &src));  // one fix, no rate
  p.addLostInSpaceFix(fixAt(0.1, w, q0));
  const auto rm = p.predict(0.2, std::nullopt, std::nullopt, &src);
  ASSERT_TRUE(rm);
  EXPECT_EQ(src, PredictionSource::kRateMatch);
  EXPECT_LT(attitudeError(rm->q_ic, fixAt(0.2, w, q0).q_ic).total, 1e-12);
  EXPECT_LT((rm->rate_cam - w).norm(), 1e-12);
  // Extrapolating one interval: (2k + k^2) + k^2 = 4 fix covariances, plus the acceleration.
  EXPECT_GT(rm->cov_cam(0, 0), 4e-10);

  const Vec3 gyro(0.01, 0.0, 0.0);
  const auto g = p.predict(0.2, std::nullopt, gyro, &src);
  ASSERT_TRUE(g);
  EXPECT_EQ(src, PredictionSource::kGyro);
  EXPECT_LT(attitudeError(g->q_ic, canonical(fixAt(0.1, w, q0).q_ic * quatExp(gyro * 0.1))).total,
            1e-12);

  CameraPrediction ext;
  ext.q_ic = q0;
  const auto e = p.predict(0.2, ext, gyro, &src);
  ASSERT_TRUE(e);
  EXPECT_EQ(src, PredictionSource::kExternal);
  EXPECT_EQ(e->q_ic.coeffs(), q0.coeffs());

  EXPECT_FALSE(p.predict(5.0, std::nullopt, std::nullopt, &src));  // older than max_propagation
  p.reset();
  EXPECT_FALSE(p.predict(0.2, std::nullopt, gyro, &src));
}

TEST(FramePredictor, AccelerationCorrectionIsATwentyFourthOfTheExposureSquared) {
  FramePredictorOptions o;
  o.exposure_s = 0.2;
  FramePredictor p(o);
  CameraFix fix{0.1, Quat::Identity(), Mat3::Zero()};
  const Vec3 w0(0.0, 0.0, 0.0), w1(0.1, 0.0, 0.0);  // 1 rad/s^2 over 0.1 s
  EXPECT_FALSE(p.correctForAcceleration(w1, fix));  // no earlier rate
  p.recordRate(0.0, w0);
  ASSERT_TRUE(p.correctForAcceleration(w1, fix));
  EXPECT_NEAR(quatLog(fix.q_ic).x(), -0.2 * 0.2 / 24.0 * 1.0, 1e-12);
  EXPECT_GT(fix.cov_cam(0, 0), 0.0);
  // A rate change below 3 sigma of the gyro noise is left alone.
  CameraFix still{0.1, Quat::Identity(), Mat3::Zero()};
  EXPECT_FALSE(p.correctForAcceleration(Vec3(1e-4, 0, 0), still));
}

}  // namespace
}  // namespace st

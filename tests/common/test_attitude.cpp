// Conventions: quaternion exp/log, RA/Dec/roll and the attitude-error split.
#include <gtest/gtest.h>

#include <random>

#include "common/attitude.hpp"
#include "common/conventions.hpp"
#include "common/mrpt_convert.hpp"

namespace st {
namespace {

Quat randomAttitude(std::mt19937_64& rng) {
  std::normal_distribution<double> n;
  return canonical(Quat(n(rng), n(rng), n(rng), n(rng)));
}

TEST(Attitude, ExpLogRoundTripIncludingTinyAndNearPi) {
  std::mt19937_64 rng(1);
  std::normal_distribution<double> n;
  for (double scale : {1e-9, 1e-5, 0.1, 1.0, 3.1}) {
    for (int i = 0; i < 200; ++i) {
      Vec3 v(n(rng), n(rng), n(rng));
      v = v.normalized() * scale;
      EXPECT_LT((quatLog(quatExp(v)) - v).norm(), 1e-12 * std::max(1.0, scale)) << scale;
    }
  }
  // A half turn: log gives angle pi (either sign of the axis is the same rotation).
  const Vec3 half = quatLog(quatExp(Vec3(0, 0, kPi)));
  EXPECT_NEAR(half.norm(), kPi, 1e-12);
}

TEST(Attitude, QuaternionMatrixAndMrptRoundTrip) {
  std::mt19937_64 rng(2);
  for (int i = 0; i < 500; ++i) {
    const Quat q = randomAttitude(rng);
    const Quat back = canonical(Quat(q.toRotationMatrix()));
    EXPECT_LT((back.coeffs() - q.coeffs()).norm(), 1e-12);
    const auto m = toMrpt(q);
    EXPECT_DOUBLE_EQ(m.r(), q.w());  // MRPT stores w first
    EXPECT_LT((fromMrpt(m).coeffs() - q.coeffs()).norm(), 1e-15);
    EXPECT_LT((fromPose3DQuat(toPose3DQuat(q)).coeffs() - q.coeffs()).norm(), 1e-12);
    // MRPT's rotation matrix equals Eigen's: v_i = R(q_ib) v_b in both libraries.
    mrpt::math::CMatrixDouble33 R;
    m.rotationMatrixNoResize(R);
    const Mat3 Re = q.toRotationMatrix();
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(R(r, c), Re(r, c), 1e-12);
  }
}

TEST(Attitude, RaDecRollRoundTrip) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0, 1);
  for (int i = 0; i < 1000; ++i) {
    RaDecRoll rdr{kTwoPi * u(rng), std::asin(2 * u(rng) - 1) * 0.999, kPi * (2 * u(rng) - 1)};
    const Quat q = attitudeFromRaDecRoll(rdr);
    const RaDecRoll back = raDecRollFromAttitude(q);
    EXPECT_NEAR(back.ra, rdr.ra, 1e-9);
    EXPECT_NEAR(back.dec, rdr.dec, 1e-9);
    EXPECT_NEAR(std::remainder(back.roll - rdr.roll, kTwoPi), 0.0, 1e-9);
    // The boresight is the camera +z axis in inertial.
    EXPECT_LT((q * Vec3::UnitZ() - unitVectorFromRaDec(rdr.ra, rdr.dec)).norm(), 1e-12);
  }
}

TEST(Attitude, RollZeroShowsNorthUpEastLeft) {
  const Quat q = attitudeFromRaDecRoll({deg2rad(30), deg2rad(20), 0});
  // Image "up" is -y in the camera: it must point to increasing declination.
  const Vec3 up_i = q * Vec3(0, -1, 0);
  double ra, dec;
  raDecFromVector(q * Vec3::UnitZ() + 0.01 * up_i, ra, dec);
  EXPECT_GT(dec, deg2rad(20));
  // Image "left" is -x: it must point to increasing RA (east).
  raDecFromVector(q * Vec3::UnitZ() + 0.01 * (q * Vec3(-1, 0, 0)), ra, dec);
  EXPECT_GT(ra, deg2rad(30));
}

TEST(Attitude, ErrorSplitPureRollAndPureCrossBoresight) {
  std::mt19937_64 rng(4);
  for (int i = 0; i < 100; ++i) {
    const Quat q_true = randomAttitude(rng);
    // Pure roll: rotate the estimate about its own boresight.
    const double roll = 0.01 * (i + 1) - 0.5;
    const Quat q_roll = q_true * quatExp(Vec3(0, 0, roll));
    AttitudeError e = attitudeError(q_roll, q_true);
    EXPECT_NEAR(e.total, std::abs(roll), 1e-12);
    EXPECT_NEAR(e.roll, -roll, 1e-12);  // est = true*Rz(roll): true = est*Rz(-roll)
    EXPECT_NEAR(e.cross_boresight, 0.0, 1e-12);
    // Pure cross-boresight: a rotation about an axis perpendicular to z.
    const double tilt = 0.003 * (i + 1);
    const Vec3 axis = Vec3(std::cos(i), std::sin(i), 0);
    const Quat q_tilt = q_true * quatExp(tilt * axis);
    e = attitudeError(q_tilt, q_true);
    EXPECT_NEAR(e.total, tilt, 1e-12);
    EXPECT_NEAR(e.cross_boresight, tilt, 1e-12);
    EXPECT_NEAR(e.roll, 0.0, 1e-12);
    // The boresight angle is what cross-boresight means.
    const double angle = std::acos(std::clamp((q_tilt * Vec3::UnitZ()).dot(q_true * Vec3::UnitZ()), -1.0, 1.0));
    EXPECT_NEAR(e.cross_boresight, angle, 1e-7);
  }
}

TEST(Attitude, JulianYearConversion) {
  // 2000-01-01T12:00:00 UTC is Unix 946728000 s, i.e. J2000.0 (ignoring TT-UTC).
  EXPECT_NEAR(julianYearFromUnixSeconds(946728000.0), 2000.0, 1e-12);
  EXPECT_NEAR(unixSecondsFromJulianYear(julianYearFromUnixSeconds(1.5e9)), 1.5e9, 1e-4);
}

}  // namespace
}  // namespace st

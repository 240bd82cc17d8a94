// Several camera heads in the one fusion loop (fusion/fusion_loop.hpp): the frames of one
// time stamp are one step; heads that agree become one joint fix, heads that disagree are
// never merged (with a filter each goes through its gate, without one the step has no fix).
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "common/attitude.hpp"
#include "common/conventions.hpp"
#include "fusion/fusion_loop.hpp"

namespace st {
namespace {

const Quat kQ0 = attitudeFromRaDecRoll({0.5, 0.2, 0.1});
const double kSigma = arcsec2rad(2);

/// A head's fix: pointing sigma across its boresight, 7x that about it (one head's roll),
/// in the body frame for a head mounted with R_body_cam.
FrameResult headFix(const Quat& q_ib, const Mat3& R_body_cam) {
  FrameResult f;
  f.mode = StarTrackerMode::kTracking;
  f.q_ib = q_ib;
  const Mat3 cam = Vec3(kSigma * kSigma, kSigma * kSigma, 49 * kSigma * kSigma).asDiagonal();
  f.cov_body = R_body_cam * cam * R_body_cam.transpose();
  f.R_body_cam = R_body_cam;
  return f;
}

const Mat3 kSideways = quatExp(deg2rad(90.0) * Vec3::UnitY()).toRotationMatrix();

struct HeadsRun {
  std::vector<FusionStep> steps;  // copies (frame pointers not kept)
  std::vector<std::size_t> heads;
  std::vector<Mat3> fix_cov;
  std::vector<std::string> detail;
};

/// 2 s of a still gyro at 100 Hz, both heads' fixes at 5 Hz; head 2's attitude off by `off`
/// (body frame) from t_off on.
HeadsRun run(FusionOptions o, const Vec3& off, double t_off) {
  o.reorder_window_s = 0.05;
  FusionLoop loop(o);
  HeadsRun r;
  loop.setStepCallback([&](const FusionStep& s) {
    if (!s.is_frame) return;
    r.steps.push_back(s);
    r.heads.push_back(s.heads.size());
    r.fix_cov.push_back(s.frame->cov_body);
    r.detail.push_back(s.frame->detail);
  });
  uint64_t tag = 0;
  for (int k = 0; k <= 200; ++k) {
    const double t = 0.01 * k;
    loop.pushGyro(t, Vec3::Zero());
    if (k % 20 != 0) continue;
    loop.pushFix(t, tag++, headFix(kQ0, Mat3::Identity()), 0);
    const Quat q2 = t >= t_off ? Quat(kQ0 * quatExp(off)) : kQ0;
    loop.pushFix(t, tag++, headFix(q2, kSideways), 1);
  }
  loop.flush();
  return r;
}

TEST(FusionHeads, TheFramesOfOneTimeAreOneJointFixGoodAboutEveryAxis) {
  const HeadsRun r = run(FusionOptions{}, Vec3::Zero(), 1e9);
  ASSERT_EQ(r.steps.size(), 11u);
  for (std::size_t i = 0; i < r.steps.size(); ++i) {
    EXPECT_EQ(r.heads[i], 2u);
    EXPECT_TRUE(r.steps[i].heads_merged);
    EXPECT_EQ(r.steps[i].heads_dof, 3);
    // Head 1's weak roll (body z) is head 2's pointing: the joint sigma is ~kSigma on
    // every axis (x: head 2's roll, 7 sigma, and head 1's pointing -> sigma / sqrt(1 + 1/49)).
    for (int a = 0; a < 3; ++a) EXPECT_LT(std::sqrt(r.fix_cov[i](a, a)), 1.01 * kSigma) << a;
  }
  EXPECT_EQ(r.steps[0].use, FixUse::kInitialized);
  EXPECT_EQ(r.steps[1].use, FixUse::kAccepted);
}

TEST(FusionHeads, HeadsThatDisagreeAreNotMergedAndTheGateRefusesTheWrongOne) {
  // Head 2 off by 30 sigma about body y (across both boresights) from t = 1 s.
  const HeadsRun r = run(FusionOptions{}, Vec3(0, 30 * kSigma, 0), 1.0);
  int merged = 0, split = 0;
  for (const FusionStep& s : r.steps) {
    (s.heads_merged ? merged : split) += 1;
    if (!s.heads_merged) {
      EXPECT_GT(s.heads_chi2, 100);
      // The step reports the head the filter took: head 1, whose fix agrees with it.
      EXPECT_EQ(s.use, FixUse::kAccepted);
    }
  }
  EXPECT_EQ(merged, 5);  // t = 0 .. 0.8 s
  EXPECT_EQ(split, 6);   // t = 1.0 .. 2.0 s
}

TEST(FusionHeads, WithoutAFilterHeadsThatDisagreeGiveNoFix) {
  FusionOptions o;
  o.filter_enabled = false;
  const HeadsRun r = run(o, Vec3(0, 30 * kSigma, 0), 1.0);
  for (std::size_t i = 0; i < r.steps.size(); ++i) {
    const bool late = r.steps[i].t >= 1.0;
    EXPECT_EQ(r.steps[i].heads_merged, !late) << r.steps[i].t;
    EXPECT_EQ(r.steps[i].use, late ? FixUse::kNoFix : FixUse::kUnfiltered) << r.steps[i].t;
    if (late) {
      EXPECT_EQ(r.detail[i], "heads disagree");
    }
  }
}

}  // namespace
}  // namespace st

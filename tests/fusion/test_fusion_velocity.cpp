// FusionLoop's observer velocity (issue 16 item 3): the newest VELOCITY sample up to a frame
// goes to its tracker, a stale one goes nowhere (one warning), and bad samples are dropped.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "common/conventions.hpp"
#include "fusion/fusion_loop.hpp"

namespace st {
namespace {

bool hasWarning(const FusionLoop& loop, const std::string& what) {
  const auto& w = loop.warnings();
  return std::any_of(w.begin(), w.end(),
                     [&](const std::string& m) { return m.find(what) != std::string::npos; });
}

TEST(FusionVelocity, AFrameGetsTheNewestSampleUpToItsTimeHeldOrProcessed) {
  FusionOptions o;
  o.reorder_window_s = 0.05;
  FusionLoop loop(o);
  const Vec3 v0(0, 0, 7.5), v1(0, 7.5, 0), v2(7.5, 0, 0);
  EXPECT_FALSE(loop.frameInputs(0.0).observer_velocity_km_s);
  loop.pushVelocity(0.0, v0);
  loop.pushVelocity(1.0, v1);
  loop.pushVelocity(2.0, v2);  // not due before t = 2
  // Still held for ordering (newest event 2.0): frameInputs looks at them too.
  ASSERT_TRUE(loop.frameInputs(0.5).observer_velocity_km_s);
  EXPECT_EQ(*loop.frameInputs(0.5).observer_velocity_km_s, v0);
  EXPECT_EQ(*loop.frameInputs(1.0).observer_velocity_km_s, v1);
  EXPECT_EQ(*loop.frameInputs(1.99).observer_velocity_km_s, v1);
  loop.flush();  // processed: the same answers
  EXPECT_EQ(*loop.frameInputs(1.5).observer_velocity_km_s, v1);
  EXPECT_EQ(*loop.frameInputs(2.5).observer_velocity_km_s, v2);
}

TEST(FusionVelocity, AStaleSampleIsNotUsedAndSaysSoOnce) {
  FusionOptions o;
  o.max_velocity_age_s = 10;
  FusionLoop loop(o);
  loop.pushVelocity(0.0, Vec3(0, 0, 7.5));
  loop.flush();
  EXPECT_TRUE(loop.frameInputs(10.0).observer_velocity_km_s);
  EXPECT_FALSE(loop.frameInputs(10.5).observer_velocity_km_s);
  EXPECT_FALSE(loop.frameInputs(11.0).observer_velocity_km_s);
  EXPECT_EQ(std::count_if(loop.warnings().begin(), loop.warnings().end(),
                          [](const std::string& w) { return w.find("max_velocity_age_s") != std::string::npos; }),
            1);
}

TEST(FusionVelocity, SamplesAreIgnoredWhenTheCorrectionIsOffAndBadOnesDropped) {
  FusionOptions off;
  off.velocity_aberration = false;
  FusionLoop a(off);
  a.pushVelocity(0.0, Vec3(0, 0, 7.5));
  a.flush();
  EXPECT_FALSE(a.frameInputs(0.1).observer_velocity_km_s);
  EXPECT_TRUE(hasWarning(a, "velocity_aberration is off"));

  FusionLoop b{FusionOptions{}};
  b.pushVelocity(0.0, Vec3(0, std::numeric_limits<double>::quiet_NaN(), 0));
  b.pushVelocity(0.1, Vec3(0, 0, 0.2 * kSpeedOfLightKmS));
  b.flush();
  EXPECT_FALSE(b.frameInputs(0.2).observer_velocity_km_s);
  EXPECT_EQ(b.warningCount(), 2);

  FusionOptions bad;
  bad.max_velocity_age_s = -1;
  std::string why;
  EXPECT_FALSE(bad.isValid(&why));
  EXPECT_NE(why.find("max_velocity_age_s"), std::string::npos) << why;
}

}  // namespace
}  // namespace st

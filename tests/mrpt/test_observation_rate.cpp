// CObservationStarTracker version 3 (issue 16): the body rate since the previous fix with its
// covariance. Round trips exactly with and without a rate; versions 0-2 still read (no rate)
// and are written back in their own layout; a version-3 object written as version 2 drops
// exactly the rate bytes; a corrupt rate flag is refused; the description shows the rate;
// FrameResult <-> observation carries it; MRPT's stock rawlog-edit lists version-3 objects.
#include <gtest/gtest.h>
#include <mrpt/serialization/CArchive.h>
#include <mrpt/serialization/CSerializable.h>

#include <cstring>
#include <regex>
#include <sstream>

#include "common/conventions.hpp"
#include "sensors/mrpt/observation_from_frame.hpp"
#include "sensors/mrpt/observation_star_tracker.hpp"
#include "sensors/mrpt/rawlog_io.hpp"
#include "tests/mrpt/mrpt_test_helpers.hpp"
#include "tests/support/test_paths.hpp"

namespace st {
namespace {

using test::Bytes;
using test::deserialize;
using test::serialize;
using test::versionOffset;

MeasuredRate sampleRate() {
  MeasuredRate r;
  r.rate_body = Vec3(deg2rad(0.31), deg2rad(-0.72), deg2rad(1.05));
  Mat3 a;
  a << 1, 0.2, -0.1, 0, 2, 0.3, 0, 0, 5;
  r.cov_body = 1e-9 * a * a.transpose();
  r.interval_s = 0.2;
  r.stars = 17;
  return r;
}

CObservationStarTracker::Ptr withRate(uint64_t seed) {
  auto o = test::makeStarTrackerObservation(seed);
  o->rate = sampleRate();
  return o;
}

TEST(ObservationRate, VersionThreeRoundTripsWithAndWithoutARate) {
  registerStarTrackerClasses();
  const auto obs = withRate(21);
  const Bytes a = serialize(*obs);
  ASSERT_EQ(a[versionOffset()], 3);
  ASSERT_EQ(CObservationStarTracker::kCurrentVersion, 3);
  const auto back = deserialize(a);
  ASSERT_NE(back, nullptr);
  ASSERT_TRUE(back->rate);
  EXPECT_EQ(*back->rate, *obs->rate);
  EXPECT_TRUE(back->sameContent(*obs));
  EXPECT_EQ(serialize(*back), a);

  const auto none = test::makeStarTrackerObservation(21);
  const Bytes b = serialize(*none);
  const auto back_none = deserialize(b);
  ASSERT_NE(back_none, nullptr);
  EXPECT_FALSE(back_none->rate);
  EXPECT_TRUE(back_none->sameContent(*none));
  // The rate costs a presence byte, 3 + 9 + 1 doubles and an int32.
  EXPECT_EQ(a.size() - b.size(), 13 * sizeof(double) + sizeof(int32_t));
  EXPECT_FALSE(back_none->sameContent(*obs));  // the comparison sees the rate
}

TEST(ObservationRate, OlderVersionsReadWithoutARateAndKeepTheirLayout) {
  registerStarTrackerClasses();
  auto obs = withRate(22);
  const Bytes v3 = serialize(*obs);
  obs->setWriteVersion(2);
  const Bytes v2 = serialize(*obs);
  ASSERT_EQ(v2[versionOffset()], 2);
  // Version 2 is version 3 without the rate block (flag + 13 doubles + int32).
  EXPECT_EQ(v3.size() - v2.size(), 1 + 13 * sizeof(double) + sizeof(int32_t));
  for (uint8_t v : {uint8_t(2), uint8_t(1), uint8_t(0)}) {
    obs->setWriteVersion(v);
    const Bytes old = serialize(*obs);
    const auto back = deserialize(old);
    ASSERT_NE(back, nullptr) << int(v);
    EXPECT_EQ(back->writeVersion(), v);
    EXPECT_FALSE(back->rate) << int(v);
    EXPECT_EQ(serialize(*back), old) << int(v);  // copied in its own layout
    // Upgraded: written as version 3 with no rate, read back the same.
    back->setWriteVersion(CObservationStarTracker::kCurrentVersion);
    const auto up = deserialize(serialize(*back));
    ASSERT_NE(up, nullptr);
    EXPECT_FALSE(up->rate);
    EXPECT_TRUE(up->sameContent(*back));
  }
}

TEST(ObservationRate, CorruptRateFlagIsRefused) {
  registerStarTrackerClasses();
  const auto none = test::makeStarTrackerObservation(23);
  Bytes b = serialize(*none);
  // The flag is the last data byte of an object without a rate (before MRPT's end marker).
  uint8_t& flag = b[b.size() - 2];
  ASSERT_EQ(flag, 0);
  flag = 2;
  EXPECT_ANY_THROW(deserialize(b));
  // A flag promising a rate that is not there: the data ends early.
  flag = 1;
  EXPECT_ANY_THROW(deserialize(b));
}

TEST(ObservationRate, DescriptionAndFrameConversionCarryTheRate) {
  auto obs = withRate(24);
  std::ostringstream text;
  obs->getDescriptionAsText(text);
  EXPECT_NE(text.str().find("Body rate since the previous fix [deg/s]: 0.31"), std::string::npos)
      << text.str();
  EXPECT_NE(text.str().find("17 common stars"), std::string::npos) << text.str();
  const FrameResult f = frameFromObservation(*obs);
  ASSERT_TRUE(f.rate);
  EXPECT_EQ(*f.rate, *obs->rate);
  const auto again = observationFromFrame(f, obs->timestamp, obs->sensorLabel, obs->sensor_pose);
  ASSERT_TRUE(again->rate);
  EXPECT_EQ(*again->rate, *obs->rate);
  obs->rate.reset();
  std::ostringstream none;
  obs->getDescriptionAsText(none);
  EXPECT_NE(none.str().find("Body rate: none"), std::string::npos);
}

#ifdef ST_MRPT_PLUGIN_PATH
TEST(ObservationRate, StockRawlogEditListsVersionThreeObjects) {
  registerStarTrackerClasses();
  const std::string path = test::makeTempDir("obs_rate_edit") + "/rates.rawlog";
  {
    RawlogWriter w(path);
    for (int k = 0; k < 6; ++k) w.write(*withRate(30 + k));
  }
  std::string info;
  ASSERT_EQ(test::runCommand(ST_PLUGIN_HOST_ENV "rawlog-edit -p '" ST_MRPT_PLUGIN_PATH
                                                "' --info -i '" + path + "'",
                             &info),
            0)
      << info;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(info, m, std::regex(R"(STAR_TRACKER\s*/\s*(\d+)\s*/)"))) << info;
  EXPECT_EQ(std::stoi(m[1]), 6) << info;
}
#endif

}  // namespace
}  // namespace st

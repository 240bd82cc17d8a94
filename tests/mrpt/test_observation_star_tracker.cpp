// CObservationStarTracker: serialization (current and older version), rawlog round trip bit for
// bit, text description, registration.
#include <gtest/gtest.h>
#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/obs/CRawlog.h>
#include <mrpt/rtti/CObject.h>
#include <mrpt/serialization/CArchive.h>
#include <mrpt/serialization/CSerializable.h>

#include <cstring>
#include <random>

#include "common/conventions.hpp"
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

Bytes decompressFile(const std::string& path) {
  mrpt::io::CFileGZInputStream f(path);
  Bytes out;
  uint8_t buf[4096];
  for (;;) {
    const std::size_t n = f.Read(buf, sizeof(buf));
    if (n == 0) break;
    out.insert(out.end(), buf, buf + n);
  }
  return out;
}

TEST(ObservationStarTracker, RegistrationIsIdempotentAndFindsTheClass) {
  registerStarTrackerClasses();
  registerStarTrackerClasses();
  const auto* cls = mrpt::rtti::findRegisteredClass("st::CObservationStarTracker");
  ASSERT_NE(cls, nullptr);
  auto obj = cls->createObject();
  EXPECT_NE(std::dynamic_pointer_cast<CObservationStarTracker>(obj), nullptr);
}

TEST(ObservationStarTracker, SerializesAndDeserializesEveryFieldExactly) {
  registerStarTrackerClasses();
  const auto obs = test::makeStarTrackerObservation(7);
  const Bytes a = serialize(*obs);
  EXPECT_EQ(a[versionOffset()], CObservationStarTracker::kCurrentVersion);
  const auto back = deserialize(a);
  ASSERT_NE(back, nullptr);
  EXPECT_TRUE(back->sameContent(*obs));
  EXPECT_EQ(serialize(*back), a);
  EXPECT_EQ(back->stars.size(), obs->stars.size());
  EXPECT_EQ(back->timings.total, obs->timings.total);

  // Teeth: one ulp in one field is seen by both comparisons.
  auto changed = test::makeStarTrackerObservation(7);
  changed->stars[3].residual = std::nextafter(changed->stars[3].residual, 1.0);
  EXPECT_FALSE(changed->sameContent(*obs));
  EXPECT_NE(serialize(*changed), a);
}

TEST(ObservationStarTracker, RoundTripsThroughARawlogBitForBit) {
  registerStarTrackerClasses();
  const std::string dir = test::makeTempDir("mrpt_roundtrip");
  const std::string path = dir + "/fixes.rawlog";
  std::vector<CObservationStarTracker::Ptr> written;
  Bytes expected_stream;
  {
    RawlogWriter w(path);
    for (int k = 0; k < 25; ++k) {
      written.push_back(test::makeStarTrackerObservation(100 + k));
      w.write(*written.back());
      const Bytes b = serialize(*written.back());
      expected_stream.insert(expected_stream.end(), b.begin(), b.end());
    }
    EXPECT_EQ(w.count(), 25u);
  }
  // The file holds exactly the serialized objects one after the other, nothing else.
  EXPECT_EQ(decompressFile(path), expected_stream);

  RawlogReader r(path);
  std::size_t k = 0;
  while (auto o = r.next()) {
    ASSERT_LT(k, written.size());
    auto st_obs = std::dynamic_pointer_cast<CObservationStarTracker>(o);
    ASSERT_NE(st_obs, nullptr) << "object " << k;
    EXPECT_TRUE(st_obs->sameContent(*written[k])) << "object " << k;
    EXPECT_EQ(serialize(*st_obs), serialize(*written[k])) << "object " << k;
    ++k;
  }
  EXPECT_EQ(k, written.size());
  EXPECT_EQ(r.count(), written.size());
}

TEST(ObservationStarTracker, OlderVersionZeroStillLoads) {
  registerStarTrackerClasses();
  auto obs = test::makeStarTrackerObservation(11);
  obs->setWriteVersion(1);
  const Bytes v1 = serialize(*obs);
  obs->setWriteVersion(0);
  const Bytes v0 = serialize(*obs);
  ASSERT_EQ(v0[versionOffset()], 0);
  // Version 0 is version 1 without the four timing doubles.
  EXPECT_EQ(v1.size() - v0.size(), 4 * sizeof(double));

  // Through a rawlog file, as an old recording would be read.
  const std::string path = test::makeTempDir("mrpt_v0") + "/old.rawlog";
  {
    RawlogWriter w(path);
    w.write(*obs);
  }
  const auto all = readRawlog(path);
  ASSERT_EQ(all.size(), 1u);
  auto back = std::dynamic_pointer_cast<CObservationStarTracker>(all[0]);
  ASSERT_NE(back, nullptr);
  EXPECT_EQ(back->writeVersion(), 0);
  EXPECT_EQ(back->timings, StageTimings{});  // unknown in version 0
  auto expected = test::makeStarTrackerObservation(11);
  expected->timings = StageTimings{};
  EXPECT_TRUE(back->sameContent(*expected));
  EXPECT_EQ(serialize(*back), v0);  // an old object is copied in its old layout

  // Upgrading: the same object written at the current version again.
  back->setWriteVersion(CObservationStarTracker::kCurrentVersion);
  EXPECT_EQ(serialize(*back)[versionOffset()], CObservationStarTracker::kCurrentVersion);
  EXPECT_THROW(back->setWriteVersion(CObservationStarTracker::kCurrentVersion + 1),
               std::invalid_argument);
}

TEST(ObservationStarTracker, VersionTwoKeepsTheFailureKindAndOlderVersionsDefaultIt) {
  registerStarTrackerClasses();
  auto obs = test::makeStarTrackerObservation(12);
  obs->mode = StarTrackerMode::kFailed;
  obs->failure = FrameFailure::kTooFewInGate;
  obs->setWriteVersion(2);  // version 3 added the rate (test_observation_rate.cpp)
  const Bytes v2 = serialize(*obs);
  ASSERT_EQ(v2[versionOffset()], 2);
  auto back = deserialize(v2);
  ASSERT_NE(back, nullptr);
  EXPECT_EQ(back->failure, FrameFailure::kTooFewInGate);
  EXPECT_TRUE(back->sameContent(*obs));
  EXPECT_EQ(serialize(*back), v2);

  // Version 1 is version 2 without the failure byte; its failures read as kUnknown...
  obs->setWriteVersion(1);
  const Bytes v1 = serialize(*obs);
  ASSERT_EQ(v1[versionOffset()], 1);
  EXPECT_EQ(v2.size() - v1.size(), 1u);
  back = deserialize(v1);
  ASSERT_NE(back, nullptr);
  EXPECT_EQ(back->writeVersion(), 1);
  EXPECT_EQ(back->failure, FrameFailure::kUnknown);
  EXPECT_EQ(serialize(*back), v1);
  // ...and its fixes as kNone.
  obs->mode = StarTrackerMode::kTracking;
  obs->failure = FrameFailure::kNone;
  back = deserialize(serialize(*obs));
  ASSERT_NE(back, nullptr);
  EXPECT_EQ(back->failure, FrameFailure::kNone);
  EXPECT_TRUE(back->sameContent(*obs));

  // A failure value beyond the enum is a corrupt object. The failure byte is where the
  // version-2 bytes first differ from the version-1 ones after the version byte.
  std::size_t at = versionOffset() + 1;
  while (at < v1.size() && v1[at] == v2[at]) ++at;
  ASSERT_EQ(v2[at], static_cast<uint8_t>(FrameFailure::kTooFewInGate));
  Bytes bad = v2;
  bad[at] = 0xff;
  EXPECT_ANY_THROW(deserialize(bad));
}

TEST(ObservationStarTracker, UnknownFutureVersionIsRejected) {
  registerStarTrackerClasses();
  Bytes b = serialize(*test::makeStarTrackerObservation(3));
  b[versionOffset()] = CObservationStarTracker::kCurrentVersion + 1;
  EXPECT_ANY_THROW(deserialize(b));

  const std::string path = test::makeTempDir("mrpt_future") + "/future.rawlog";
  test::writePlainFile(path, b);
  try {
    readRawlog(path);
    FAIL() << "a future version must not load";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("object 0"), std::string::npos) << e.what();
  }
}

TEST(ObservationStarTracker, DescriptionShowsEverythingRawLogViewerNeeds) {
  auto obs = test::makeStarTrackerObservation(5);
  obs->sensorLabel = "STAR_TRACKER";
  const std::string text = obs->asString();
  for (const char* key : {"STAR_TRACKER", "Mode: tracking", "q_ib (w x y z)", "RA / Dec / roll",
                          "Covariance", "Detected blobs: 42", "Timings [ms]", "Matched stars: 8",
                          "Reason: test fix", "Sensor pose"}) {
    EXPECT_NE(text.find(key), std::string::npos) << key << "\n" << text;
  }
  EXPECT_NE(text.find(std::to_string(obs->stars[0].catalog_id)), std::string::npos);

  obs->mode = StarTrackerMode::kFailed;
  obs->failure = FrameFailure::kNoMatch;
  EXPECT_NE(obs->asString().find("No attitude"), std::string::npos);
  EXPECT_NE(obs->asString().find("Failure: no-match"), std::string::npos);
}

}  // namespace
}  // namespace st

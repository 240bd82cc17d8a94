// Rawlog writer/reader: object counts, the silent-truncation trap of MRPT's CRawlog, clear
// errors for missing / truncated / garbage files, external images, and the stock
// `rawlog-edit -p <plugin>` listing our observations.
#include <gtest/gtest.h>
#include <mrpt/hwdrivers/CGenericSensor.h>
#include <mrpt/io/CFileOutputStream.h>
#include <mrpt/obs/CObservationImage.h>
#include <mrpt/obs/CRawlog.h>
#include <mrpt/serialization/CArchive.h>
#include <mrpt/serialization/CSerializable.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <opencv2/core.hpp>

#include "common/errors.hpp"
#include "sensors/mrpt/observation_star_tracker.hpp"
#include "sensors/mrpt/rawlog_io.hpp"
#include "sensors/sim/simulated_sensors.hpp"
#include "tests/mrpt/mrpt_test_helpers.hpp"
#include "tests/support/test_paths.hpp"

// An observation type that is deliberately never registered with mrpt::rtti: it stands for
// any class a reader does not know (ours without the plugin, a newer tool's type, ...).
namespace st::test {
class CObservationNeverRegistered : public mrpt::obs::CObservation {
  DEFINE_SERIALIZABLE(CObservationNeverRegistered, st::test)
 public:
  double value = 1.5;
  void getSensorPose(mrpt::poses::CPose3D& p) const override { p = mrpt::poses::CPose3D(); }
  void setSensorPose(const mrpt::poses::CPose3D&) override {}
  using CObservation::getSensorPose;
  using CObservation::setSensorPose;
};
IMPLEMENTS_SERIALIZABLE(CObservationNeverRegistered, mrpt::obs::CObservation, st::test)
uint8_t CObservationNeverRegistered::serializeGetVersion() const { return 0; }
void CObservationNeverRegistered::serializeTo(mrpt::serialization::CArchive& out) const {
  out << timestamp << sensorLabel << value;
}
void CObservationNeverRegistered::serializeFrom(mrpt::serialization::CArchive& in, uint8_t) {
  in >> timestamp >> sensorLabel >> value;
}
}  // namespace st::test

namespace st {
namespace {

namespace fs = std::filesystem;

bool contains(const std::string& s, const std::string& what) {
  return s.find(what) != std::string::npos;
}

/// Writes `n_before` gyro samples, then one STAR_TRACKER fix, repeated `blocks` times.
std::size_t writeMixedRawlog(const std::string& path, int blocks, int n_before) {
  RawlogWriter w(path);
  double t = 0;
  for (int b = 0; b < blocks; ++b) {
    for (int i = 0; i < n_before; ++i) w.write(*test::makeGyroObservation(t += 0.01));
    w.write(*test::makeStarTrackerObservation(b));
  }
  return w.count();
}

TEST(RawlogIo, NumberOfObjectsReadEqualsNumberWritten) {
  registerStarTrackerClasses();
  const std::string path = test::makeTempDir("rawlog_count") + "/mixed.rawlog";
  const std::size_t written = writeMixedRawlog(path, 12, 4);
  ASSERT_EQ(written, 12u * 5u);

  RawlogReader r(path);
  std::size_t fixes = 0, gyros = 0;
  while (auto o = r.next()) {
    if (IS_CLASS(*o, CObservationStarTracker)) ++fixes;
    if (IS_CLASS(*o, mrpt::obs::CObservationIMU)) ++gyros;
  }
  EXPECT_EQ(r.count(), written);
  EXPECT_EQ(fixes, 12u);
  EXPECT_EQ(gyros, 48u);
  EXPECT_EQ(r.next(), nullptr);  // stays at the end

  // With registration done, MRPT's own loader agrees.
  mrpt::obs::CRawlog log;
  ASSERT_TRUE(log.loadFromRawLogFile(path));
  EXPECT_EQ(log.size(), written);
}

TEST(RawlogIo, UnknownClassTruncatesCRawlogSilentlyButOurReaderReportsIt) {
  registerStarTrackerClasses();
  const std::string path = test::makeTempDir("rawlog_unknown") + "/unknown.rawlog";
  {
    RawlogWriter w(path);
    for (int i = 0; i < 3; ++i) w.write(*test::makeGyroObservation(i));
    w.write(test::CObservationNeverRegistered());
    for (int i = 0; i < 3; ++i) w.write(*test::makeGyroObservation(10 + i));
    ASSERT_EQ(w.count(), 7u);
  }
  // The trap (MRPT-NOTES.md): CRawlog says "success" and keeps only what came before.
  mrpt::obs::CRawlog log;
  EXPECT_TRUE(log.loadFromRawLogFile(path));
  EXPECT_EQ(log.size(), 3u);

  // Our reader: an InputError naming the file and the object index.
  RawlogReader r(path);
  for (int i = 0; i < 3; ++i) ASSERT_NE(r.next(), nullptr);
  try {
    r.next();
    FAIL() << "the unknown class must be reported";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_TRUE(contains(msg, path)) << msg;
    EXPECT_TRUE(contains(msg, "object 3")) << msg;
    EXPECT_TRUE(contains(msg, "not registered")) << msg;
    EXPECT_TRUE(contains(msg, "CObservationNeverRegistered")) << msg;
  }
}

TEST(RawlogIo, RegistrationRegistersTheTrackerAndTheSimulatorItsOwnSensors) {
  // rawlog-grabber -p <plugins> needs the factory to know them by their bare class names;
  // the simulator registers its sensors itself (its own plugin).
  registerStarTrackerClasses();
  EXPECT_NE(mrpt::hwdrivers::CGenericSensor::createSensorPtr("CStarTrackerSensor"), nullptr);
  registerSimulatedSensors();
  EXPECT_NE(mrpt::hwdrivers::CGenericSensor::createSensorPtr("CSimulatedStarCamera"), nullptr);
  EXPECT_NE(mrpt::hwdrivers::CGenericSensor::createSensorPtr("CSimulatedGyro"), nullptr);
}

TEST(RawlogIo, MissingFileIsAnInputErrorNamingIt) {
  const std::string path = test::makeTempDir("rawlog_missing") + "/nope.rawlog";
  try {
    RawlogReader r(path);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_TRUE(contains(e.what(), path)) << e.what();
  }
  EXPECT_THROW(RawlogWriter(path + "/sub/x.rawlog"), InputError);
}

TEST(RawlogIo, GarbageFileIsAnInputErrorNamingIt) {
  const std::string path = test::makeTempDir("rawlog_garbage") + "/notes.rawlog";
  std::ofstream(path) << "This is a text file and certainly not an MRPT rawlog.\n"
                      << "Second line with more words to read as a class name.\n";
  try {
    readRawlog(path);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_TRUE(contains(e.what(), path)) << e.what();
    EXPECT_TRUE(contains(e.what(), "object 0")) << e.what();
  }
}

TEST(RawlogIo, TruncatedFileIsAnInputErrorNamingFileAndObject) {
  registerStarTrackerClasses();
  const std::string dir = test::makeTempDir("rawlog_trunc");
  // Uncompressed stream so the cut can be placed inside a known object: the middle of the
  // sixth object (index 5).
  std::vector<uint8_t> stream;
  std::size_t cut = 0;
  for (int k = 0; k < 10; ++k) {
    std::vector<uint8_t> b;
    mrpt::serialization::ObjectToOctetVector(test::makeStarTrackerObservation(k).get(), b);
    if (k == 5) cut = stream.size() + b.size() / 2;
    stream.insert(stream.end(), b.begin(), b.end());
  }
  const std::string plain = dir + "/cut.rawlog";
  test::writePlainFile(plain, std::vector<uint8_t>(stream.begin(), stream.begin() + cut));
  {
    // Teeth: the uncut stream reads completely.
    const std::string whole = dir + "/whole.rawlog";
    test::writePlainFile(whole, stream);
    EXPECT_EQ(readRawlog(whole).size(), 10u);
  }
  RawlogReader r(plain);
  for (int k = 0; k < 5; ++k) ASSERT_NE(r.next(), nullptr) << k;
  try {
    r.next();
    FAIL() << "a cut inside object 5 must be reported";
  } catch (const InputError& e) {
    EXPECT_TRUE(contains(e.what(), plain)) << e.what();
    EXPECT_TRUE(contains(e.what(), "object 5")) << e.what();
  }

  // A gz rawlog cut in half fails too (wherever the cut falls).
  const std::string gz = dir + "/cut_gz.rawlog";
  writeMixedRawlog(gz, 30, 2);
  fs::resize_file(gz, fs::file_size(gz) / 2);
  try {
    readRawlog(gz);
    FAIL() << "a gz rawlog cut in half must be reported";
  } catch (const InputError& e) {
    EXPECT_TRUE(contains(e.what(), gz)) << e.what();
    EXPECT_TRUE(contains(e.what(), "object ")) << e.what();
  }
}

TEST(RawlogIo, ExternalImagesGoBesideTheRawlogAndLoadBack) {
  const std::string dir = test::makeTempDir("rawlog_images");
  const std::string path = dir + "/run.rawlog";
  cv::Mat img16(48, 64, CV_16UC1);
  for (int r = 0; r < img16.rows; ++r)
    for (int c = 0; c < img16.cols; ++c) img16.at<uint16_t>(r, c) = uint16_t(1000 * r + 7 * c);
  {
    RawlogWriter w(path);
    EXPECT_EQ(w.imagesDir(), dir + "/run_Images");
    auto obs = mrpt::obs::CObservationImage::Create();
    obs->sensorLabel = "CAMERA";
    obs->image = mrpt::img::CImage(img16, mrpt::img::DEEP_COPY);
    w.externalizeImage(obs->image, "CAMERA_000000.png");
    EXPECT_TRUE(obs->image.isExternallyStored());
    w.write(*obs);
  }
  EXPECT_TRUE(fs::exists(dir + "/run_Images/CAMERA_000000.png"));
  EXPECT_LT(fs::file_size(path), 1000u);  // only the name is inline

  const auto all = readRawlog(path);
  ASSERT_EQ(all.size(), 1u);
  auto obs = std::dynamic_pointer_cast<mrpt::obs::CObservationImage>(all[0]);
  ASSERT_NE(obs, nullptr);
  const cv::Mat back = obs->image.asCvMatRef();
  ASSERT_EQ(back.type(), CV_16UC1);
  EXPECT_EQ(cv::norm(back, img16, cv::NORM_INF), 0.0);
}

#ifdef ST_MRPT_PLUGIN_PATH
TEST(RawlogIo, StockRawlogEditListsStarTrackerWithThePlugin) {
  const std::string path = test::makeTempDir("rawlog_edit") + "/for_edit.rawlog";
  writeMixedRawlog(path, 6, 2);  // 6 fixes + 12 gyros

  std::string out;
  const int rc = test::runCommand(
      ST_PLUGIN_HOST_ENV "rawlog-edit -p '" ST_MRPT_PLUGIN_PATH "' --info -i '" + path + "'",
      &out);
  EXPECT_EQ(rc, 0) << out;
  const std::regex objects(R"(Overall number of objects\s*:\s*(\d+))");
  const std::regex fixes(R"(STAR_TRACKER\s*/\s*(\d+)\s*/)");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(out, m, objects)) << out;
  EXPECT_EQ(m[1], "18") << out;
  ASSERT_TRUE(std::regex_search(out, m, fixes)) << out;
  EXPECT_EQ(m[1], "6") << out;

  // Teeth: without the plugin the stock tool stops at the first fix (MRPT-NOTES.md) and
  // still exits 0: 2 gyro samples, no STAR_TRACKER.
  std::string bare;
  EXPECT_EQ(test::runCommand("rawlog-edit --info -i '" + path + "'", &bare), 0) << bare;
  ASSERT_TRUE(std::regex_search(bare, m, objects)) << bare;
  EXPECT_EQ(m[1], "2") << bare;
  EXPECT_FALSE(std::regex_search(bare, m, fixes)) << bare;
  // ... which our reader turns into an error instead, when the classes are not known; here
  // they are, so it reads all 18.
  EXPECT_EQ(readRawlog(path).size(), 18u);
}
#endif

}  // namespace
}  // namespace st

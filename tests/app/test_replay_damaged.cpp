// Issue 18, item 2: `startracker replay` of a rawlog truncated or damaged part way (a recording
// interrupted by a crash or power loss) replays every intact observation before the damage,
// says once where and why it stopped, and exits 0; --strict makes it exit 2. A file that is no
// rawlog at all stays an error.
#include <gtest/gtest.h>

#include <mrpt/obs/CObservationImage.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>
#include <vector>

#include "sensors/mrpt/rawlog_io.hpp"
#include "tests/app/test_cli_run.hpp"
#include "tests/support/test_paths.hpp"

namespace st {
namespace {

namespace fs = std::filesystem;

const char* kSample = "slew_2dps";

std::string sample() { return test::repoDir() + "/rawlogs/" + kSample + ".rawlog"; }

/// End offset (uncompressed stream) and CAMERA-ness of every object of the sample.
struct Obj {
  std::uint64_t end;
  bool camera;
};
std::vector<Obj> sampleObjects() {
  std::vector<Obj> out;
  RawlogReader r(sample());
  while (auto o = r.next()) {
    out.push_back({r.offset(), o->sensorLabel == "CAMERA" &&
                                   std::dynamic_pointer_cast<mrpt::obs::CObservationImage>(o)});
  }
  return out;
}

/// Intact objects and CAMERA frames among them when the stream holds `bytes` bytes.
std::pair<std::size_t, int> intactBefore(const std::vector<Obj>& objs, std::uint64_t bytes) {
  std::size_t n = 0;
  int cams = 0;
  for (const Obj& o : objs) {
    if (o.end > bytes) break;
    ++n;
    cams += o.camera ? 1 : 0;
  }
  return {n, cams};
}

/// `dir/t.rawlog` with the sample's images beside it as `t_Images`.
std::string withImages(const std::string& dir) {
  fs::create_directory_symlink(test::repoDir() + "/rawlogs/" + kSample + "_Images",
                               dir + "/t_Images");
  return dir + "/t.rawlog";
}

long grab(const std::string& out, const std::string& pattern) {
  std::smatch m;
  if (!std::regex_search(out, m, std::regex(pattern))) return -1;
  return std::stol(m[1]);
}

std::size_t occurrences(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (auto p = text.find(what); p != std::string::npos; p = text.find(what, p + 1)) ++n;
  return n;
}

std::uint64_t shellNumber(const std::string& cmd) {
  std::string out;
  EXPECT_EQ(test::runCommand(cmd, &out), 0) << out;
  return std::stoull(out);
}

/// The replay of a damaged copy: exit 0, the intact frames replayed, one message naming the
/// object where it stopped; then --strict: exit 2 with that message.
void expectReplaysUpToDamage(const std::string& rawlog, std::size_t objects, int frames) {
  ASSERT_GT(frames, 0);
  const test::CliRun r = test::runCli("replay -q " + rawlog);
  EXPECT_EQ(r.code, 0) << r.out << r.err;
  EXPECT_EQ(grab(r.out, R"(: (\d+) observations)"), long(objects)) << r.out;
  EXPECT_EQ(grab(r.out, R"(frames: (\d+))"), frames) << r.out;
  const std::string where = "stopped at object " + std::to_string(objects);
  EXPECT_EQ(occurrences(r.err, where), 1u) << r.err;
  EXPECT_EQ(occurrences(r.err, "stopped at object"), 1u) << r.err;
  EXPECT_NE(r.err.find("byte "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(rawlog), std::string::npos) << r.err;

  const test::CliRun s = test::runCli("replay -q --strict " + rawlog);
  EXPECT_EQ(s.code, 2) << s.out << s.err;
  EXPECT_NE(s.err.find(where), std::string::npos) << s.err;
  EXPECT_EQ(s.out.find("frames:"), std::string::npos) << s.out;  // nothing replayed
}

TEST(ReplayDamaged, UncompressedStreamCutAt60PercentReplaysTheIntactFrames) {
  const auto objs = sampleObjects();
  ASSERT_GT(objs.size(), 10u);
  std::uint64_t cut = objs.back().end * 6 / 10;
  for (const Obj& o : objs)
    if (o.end == cut) ++cut;  // inside an object, not between two
  const auto [n, frames] = intactBefore(objs, cut);
  const std::string dir = test::makeTempDir("replay_cut_stream");
  const std::string rawlog = withImages(dir);
  ASSERT_EQ(test::runCommand("zcat '" + sample() + "' | head -c " + std::to_string(cut) +
                             " | gzip > '" + rawlog + "'"),
            0);
  expectReplaysUpToDamage(rawlog, n, frames);
  EXPECT_LT(frames, 12);  // teeth: the sample has 12 frames, the cut loses some
}

TEST(ReplayDamaged, GzFileCutAt60PercentReplaysTheIntactFrames) {
  const auto objs = sampleObjects();
  const std::string dir = test::makeTempDir("replay_cut_gz");
  const std::string rawlog = withImages(dir);
  fs::copy_file(sample(), rawlog);
  fs::resize_file(rawlog, fs::file_size(rawlog) * 6 / 10);
  // What survives the cut: the bytes zlib still decodes (gzip reports the damage, exit 1).
  const std::uint64_t decodable =
      shellNumber("zcat '" + rawlog + "' 2>/dev/null | wc -c");
  const auto [n, frames] = intactBefore(objs, decodable);
  expectReplaysUpToDamage(rawlog, n, frames);
  EXPECT_LT(frames, 12);
}

TEST(ReplayDamaged, GarbageBytesInTheMiddleStopTheReplayThere) {
  const auto objs = sampleObjects();
  const std::size_t k = objs.size() * 6 / 10;  // object k's first bytes are overwritten
  const std::uint64_t at = objs[k - 1].end;
  const auto [n, frames] = intactBefore(objs, at);
  ASSERT_EQ(n, k);
  const std::string dir = test::makeTempDir("replay_garbage_mid");
  const std::string rawlog = withImages(dir);
  // The whole stream, 32 bytes of 0xA5 where object k starts, then the rest.
  ASSERT_EQ(test::runCommand("zcat '" + sample() + "' > '" + dir + "/s' && (head -c " +
                             std::to_string(at) + " '" + dir + "/s'; head -c 32 /dev/zero | " +
                             "tr '\\000' '\\245'; tail -c +" + std::to_string(at + 33) +
                             " '" + dir + "/s') | gzip > '" + rawlog + "'"),
            0);
  expectReplaysUpToDamage(rawlog, n, frames);
}

TEST(ReplayDamaged, NotARawlogStaysAnError) {
  const std::string dir = test::makeTempDir("replay_not_rawlog");
  const std::string text = dir + "/notes.rawlog";
  std::ofstream(text) << "This is a text file and certainly not an MRPT rawlog.\n";
  const std::string gz = dir + "/notes_gz.rawlog";
  ASSERT_EQ(test::runCommand("gzip -c '" + text + "' > '" + gz + "'"), 0);
  for (const std::string& f : {text, gz}) {
    const test::CliRun r = test::runCli("replay -q " + f);
    EXPECT_EQ(r.code, 2) << r.out << r.err;
    EXPECT_NE(r.err.find("object 0"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("not a rawlog"), std::string::npos) << r.err;
    EXPECT_EQ(r.out.find("frames:"), std::string::npos) << r.out;
  }
}

}  // namespace
}  // namespace st

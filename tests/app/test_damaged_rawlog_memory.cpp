// Issue 39, "allocation bounded by the input": a damaged length in a rawlog made `replay`
// allocate and touch what it declared (a 355-byte file cost 1.66 GB; others asked for 12.9,
// 22.5 and 72.6 GB and were refused only under an address-space limit). A rawlog object may
// now allocate no more than its file can describe (mrpt_allocation.hpp): the same damage is
// reported as damage at a few MB, with no memory limit set. Peak memory is measured on the
// real program (the children's maxrss, through python3's resource module).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/obs/CObservationComment.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "sensors/mrpt/mrpt_allocation.hpp"
#include "sensors/mrpt/rawlog_io.hpp"
#include "tests/app/test_cli_run.hpp"

namespace st {
namespace {

std::vector<uint8_t> uncompressed(const std::string& path) {
  mrpt::io::CFileGZInputStream in(path);
  std::vector<uint8_t> out;
  uint8_t buf[4096];
  for (std::size_t n; (n = in.Read(buf, sizeof buf)) > 0;) out.insert(out.end(), buf, buf + n);
  return out;
}

/// A one-object rawlog (a comment) whose text length field says `declared` bytes.
std::string damagedRawlog(const std::string& dir, uint32_t declared) {
  const std::string good = dir + "/good.rawlog";
  {
    RawlogWriter w(good);
    auto c = mrpt::obs::CObservationComment::Create();
    c->text = "THE-TEXT-OF-THE-COMMENT";
    w.write(*c);
  }
  std::vector<uint8_t> bytes = uncompressed(good);
  const std::string text = "THE-TEXT-OF-THE-COMMENT";
  const auto at = std::search(bytes.begin(), bytes.end(), text.begin(), text.end());
  EXPECT_NE(at, bytes.end());
  const std::size_t len_at = static_cast<std::size_t>(at - bytes.begin()) - 4;
  uint32_t len = 0;
  std::memcpy(&len, &bytes[len_at], 4);
  EXPECT_EQ(len, text.size()) << "MRPT's string length field is not where expected";
  std::memcpy(&bytes[len_at], &declared, 4);
  const std::string bad = dir + "/damaged.rawlog";
  mrpt::io::CFileGZOutputStream out(bad);
  out.Write(bytes.data(), bytes.size());
  return bad;
}

/// Runs `startracker ARGS` in `dir`; returns its peak resident memory [MB] and sets `code`.
double peakMb(const std::string& args, const std::string& dir, int* code) {
  const std::string py =
      "import resource, subprocess, sys\n"
      "r = subprocess.run(sys.argv[1:], stdout=subprocess.DEVNULL, stderr=open('err.txt', 'w'))\n"
      "print(r.returncode, resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss)\n";
  std::ofstream(dir + "/peak.py") << py;
  std::string out;
  test::runCommand("cd '" + dir + "' && python3 peak.py " + test::cliExe() + " " + args, &out);
  int rc = -1;
  long kb = -1;
  std::sscanf(out.c_str(), "%d %ld", &rc, &kb);
  *code = rc;
  return kb / 1024.0;
}

TEST(DamagedRawlogMemory, ADamagedLengthCostsAFewMegabytesNotWhatItDeclares) {
  if (!rawlogReadBudgetEnforced()) GTEST_SKIP() << "a sanitizer build keeps its own operator new";
  const std::string dir = test::makeTempDir("rawlog_memory");
  const std::string bad = damagedRawlog(dir, 0x60000000u);  // 1.5 GiB declared
  ASSERT_LT(std::filesystem::file_size(bad), 400u);         // as small as the issue's
  int code = -1;
  // The program's own baseline (its ~330 libraries: ~120 MB here): replay of a missing file.
  const double baseline_mb = peakMb("replay no-such.rawlog", dir, &code);
  EXPECT_EQ(code, 2);
  const double replay_mb = peakMb("replay damaged.rawlog", dir, &code);
  EXPECT_EQ(code, 2);
  // A few MB over the baseline (the budget is 8 MB for this file); without it the declared
  // 1.5 GiB is touched as the string is zero-filled (1641 MB measured).
  EXPECT_LT(replay_mb, baseline_mb + 32)
      << "replay of a " << std::filesystem::file_size(bad) << "-byte rawlog peaked at "
      << replay_mb << " MB, against " << baseline_mb << " MB for a missing file";
  std::ifstream err(dir + "/err.txt");
  std::stringstream ss;
  ss << err.rdbuf();
  EXPECT_THAT(ss.str(), ::testing::HasSubstr("damaged.rawlog"));
  EXPECT_THAT(ss.str(), ::testing::HasSubstr("declares more memory than this"));
}

TEST(DamagedRawlogMemory, TheBudgetFollowsTheFileSize) {
  // Deflate expands at most 1032:1: what a file can describe grows with it, capped at 1 GiB.
  EXPECT_LT(rawlogReadBudget(355), std::size_t(10) << 20);
  EXPECT_GE(rawlogReadBudget(1 << 20), std::size_t(1000) << 20);
  EXPECT_EQ(rawlogReadBudget(uint64_t(1) << 40), kMaxRawlogObjectBytes);
}

}  // namespace
}  // namespace st

// solve on many frames (issue 15 item 5): folders and files, JSON Lines in input order, one
// database for the run, --threads, the summary, the exit code (the worst frame's), and the
// on-disk database cache (keyed, safe against concurrent writers and corrupt files).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>

#include "tests/app/solve_cli_util.hpp"
#include "tests/app/test_cli_run.hpp"

namespace st {
namespace {
namespace fs = std::filesystem;

std::vector<nlohmann::json> jsonLines(const std::string& out) {
  std::vector<nlohmann::json> lines;
  std::istringstream ss(out);
  for (std::string line; std::getline(ss, line);)
    lines.push_back(nlohmann::json::parse(line, nullptr, false));
  return lines;
}

/// A cache folder of the test's own, so no run sees another's files.
std::string cacheEnv(const std::string& dir) { return "XDG_CACHE_HOME='" + dir + "' "; }

std::vector<std::string> filesIn(const std::string& dir) {
  std::vector<std::string> out;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec)) out.push_back(e.path().filename().string());
  return out;
}

TEST(SolveBatch, FolderGivesOneJsonLinePerFrameInOrderAndTheSingleFramesAttitudes) {
  const std::string cache = test::makeTempDir("batch_cache");
  const auto r = test::runCli("solve --json --fov-deg 11.4 --threads 2 " +
                                  test::shellQuote(test::tetra3ImageDir()),
                              "", cacheEnv(cache));
  ASSERT_EQ(r.code, 0) << r.err;
  const auto lines = jsonLines(r.out);
  const auto frames = test::tetra3Frames();
  ASSERT_EQ(lines.size(), frames.size()) << r.out;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    ASSERT_FALSE(lines[i].is_discarded()) << i;
    EXPECT_EQ(lines[i].at("image"), frames[i]);
    EXPECT_TRUE(lines[i].at("solved").get<bool>()) << frames[i];
  }
  EXPECT_NE(r.err.find("8 frames: 8 solved, 0 not solved, 0 errors; median"), std::string::npos)
      << r.err;
  // The batch identifies each frame as a run of its own does (same database, same search).
  const auto one = test::runCli("solve --json --fov-deg 11.4 " + test::shellQuote(frames[3]), "",
                                cacheEnv(cache));
  ASSERT_EQ(one.code, 0) << one.err;
  const auto single = nlohmann::json::parse(one.out);
  EXPECT_LT(test::attitudeDifferenceArcsec(single, lines[3]), 1e-3);
}

TEST(SolveBatch, ExitCodeIsTheWorstFramesAndEveryFrameGetsItsLine) {
  const std::string dir = test::makeTempDir("batch_mixed");
  const auto frames = test::tetra3Frames();
  fs::copy_file(frames[0], dir + "/a.tiff");
  cv::imwrite(dir + "/b_black.png", cv::Mat::zeros(64, 64, CV_8UC1));  // solves nothing: 1
  const std::string cache = test::makeTempDir("batch_cache");
  auto r = test::runCli("solve --json --fov-deg 11.4 " + test::shellQuote(dir), "", cacheEnv(cache));
  EXPECT_EQ(r.code, 1) << r.err;
  auto lines = jsonLines(r.out);
  ASSERT_EQ(lines.size(), 2u) << r.out;
  EXPECT_TRUE(lines[0].at("solved").get<bool>());
  EXPECT_FALSE(lines[1].at("solved").get<bool>());
  EXPECT_EQ(lines[1].at("exit_code"), 1);

  std::ofstream(dir + "/c_broken.png") << "not a png";  // bad input: 2, the others still run
  r = test::runCli("solve --json --fov-deg 11.4 " + test::shellQuote(dir), "", cacheEnv(cache));
  EXPECT_EQ(r.code, 2) << r.err;
  lines = jsonLines(r.out);
  ASSERT_EQ(lines.size(), 3u) << r.out;
  EXPECT_TRUE(lines[0].at("solved").get<bool>());
  EXPECT_EQ(lines[2].at("exit_code"), 2);
  EXPECT_EQ(lines[2].at("image"), dir + "/c_broken.png");
  EXPECT_NE(r.err.find("3 frames: 1 solved, 1 not solved, 1 errors"), std::string::npos) << r.err;
}

TEST(SolveBatch, BadBatchInputIsExitTwoNamingIt) {
  const std::string empty = test::makeTempDir("batch_empty");
  auto r = test::runCli("solve --fov-deg 11.4 " + test::shellQuote(empty));
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find(empty + ": a folder without images"), std::string::npos) << r.err;
  r = test::runCli("solve --fov-deg 11.4 --annotate out.png " +
                   test::shellQuote(test::tetra3ImageDir()));
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--annotate: one output file for 8 frames"), std::string::npos) << r.err;
  r = test::runCli("solve --threads 0 x.png");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("--threads"), std::string::npos) << r.err;
}

TEST(SolveDatabaseCache, SecondRunReadsTheCacheAndGetsTheSameAttitude) {
  const std::string cache = test::makeTempDir("db_cache");
  const std::string frame = test::shellQuote(test::tetra3Frame());
  const auto a = test::runCli("solve --json --fov-deg 11.4 " + frame, "", cacheEnv(cache));
  const auto b = test::runCli("solve --json --fov-deg 11.4 " + frame, "", cacheEnv(cache));
  ASSERT_EQ(a.code, 0) << a.err;
  ASSERT_EQ(b.code, 0) << b.err;
  const auto ja = nlohmann::json::parse(a.out), jb = nlohmann::json::parse(b.out);
  EXPECT_NE(ja.at("database").get<std::string>().find("cached in " + cache + "/startracker/db-"),
            std::string::npos)
      << ja.at("database");
  EXPECT_NE(jb.at("database").get<std::string>().find("read from the cache"), std::string::npos)
      << jb.at("database");
  EXPECT_EQ(test::attitudeDifferenceArcsec(ja, jb), 0.0);
  const auto c = test::runCli("solve --json --no-cache --fov-deg 11.4 " + frame, "",
                              cacheEnv(test::makeTempDir("db_nocache")));
  ASSERT_EQ(c.code, 0);
  EXPECT_NE(nlohmann::json::parse(c.out).at("database").get<std::string>().find("built in memory"),
            std::string::npos);
}

TEST(SolveDatabaseCache, ConcurrentWritersLeaveOneCompleteFile) {
  const std::string cache = test::makeTempDir("db_cache_conc");
  const std::string dir = test::makeTempDir("db_cache_runs");
  std::string cmd = "cd '" + dir + "'; ";
  const int n = 4;
  for (int k = 0; k < n; ++k)
    cmd += "(" + cacheEnv(cache) + test::cliExe() + " solve --json --fov-deg 11.4 " +
           test::shellQuote(test::tetra3Frame()) + " >out" + std::to_string(k) +
           ".json 2>/dev/null; echo $? >rc" + std::to_string(k) + ") & ";
  cmd += "wait";
  ASSERT_EQ(test::runCommand(cmd), 0);
  std::vector<nlohmann::json> js;
  for (int k = 0; k < n; ++k) {
    std::ifstream rc(dir + "/rc" + std::to_string(k));
    int code = -1;
    rc >> code;
    EXPECT_EQ(code, 0) << k;
    std::ifstream f(dir + "/out" + std::to_string(k) + ".json");
    js.push_back(nlohmann::json::parse(f, nullptr, false));
    ASSERT_FALSE(js.back().is_discarded());
    EXPECT_EQ(test::attitudeDifferenceArcsec(js[0], js.back()), 0.0);
  }
  const auto files = filesIn(cache + "/startracker");
  ASSERT_EQ(files.size(), 1u);  // no temporary file left behind
  EXPECT_EQ(files[0].rfind("db-", 0), 0u);
  // And the file is whole: the next run reads it.
  const auto r = test::runCli("solve --json --fov-deg 11.4 " + test::shellQuote(test::tetra3Frame()),
                              "", cacheEnv(cache));
  EXPECT_NE(r.out.find("read from the cache"), std::string::npos) << r.out;
}

TEST(SolveDatabaseCache, CorruptOrTruncatedFileIsRebuiltWithAWarning) {
  const std::string cache = test::makeTempDir("db_cache_bad");
  const std::string frame = test::shellQuote(test::tetra3Frame());
  ASSERT_EQ(test::runCli("solve --fov-deg 11.4 " + frame, "", cacheEnv(cache)).code, 0);
  const auto files = filesIn(cache + "/startracker");
  ASSERT_EQ(files.size(), 1u);
  const std::string path = cache + "/startracker/" + files[0];
  const auto size = fs::file_size(path);
  for (int damage = 0; damage < 2; ++damage) {
    if (damage == 0) {  // one byte flipped in the middle: the checksum catches it
      std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
      f.seekg(std::streamoff(size / 2));
      char c = 0;
      f.read(&c, 1);
      c = char(c ^ 0x5a);
      f.seekp(std::streamoff(size / 2));
      f.write(&c, 1);
    } else {
      fs::resize_file(path, size / 3);
    }
    auto r = test::runCli("solve --json --fov-deg 11.4 " + frame, "", cacheEnv(cache));
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("star database cache " + path + " is unreadable"), std::string::npos)
        << r.err;
    EXPECT_EQ(fs::file_size(path), size);  // rewritten whole
    r = test::runCli("solve --json --fov-deg 11.4 " + frame, "", cacheEnv(cache));
    EXPECT_EQ(r.err.find("unreadable"), std::string::npos) << r.err;
    EXPECT_NE(r.out.find("read from the cache"), std::string::npos);
  }
}

}  // namespace
}  // namespace st

// Issue 37, archive solving that survives, through the real program: `solve --files-from LIST
// --shard i/N -o PART.jsonl [--resume]` and `solve merge PARTS -o ALL [--files-from LIST]`.
// The shards merged equal the serial batch apart from timings; a run killed by SIGKILL and
// resumed loses and repeats no frame; a cut last line is solved again; SIGTERM (Slurm's time
// limit) stops between frames with exit 130; every misuse is refused before any work.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "tests/app/test_cli_run.hpp"

namespace st {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

// Every run builds its database in memory the same way, so the "database" key of each line
// is the same text in every process.
const std::string kSolve = "solve --fov-deg 11.4 --no-cache ";

std::vector<std::string> lines(const std::string& path) {
  std::ifstream f(path);
  std::vector<std::string> out;
  for (std::string l; std::getline(f, l);) out.push_back(l);
  return out;
}

/// The lines of a results file with their timings dropped, in file order.
std::vector<std::string> withoutTimings(const std::string& path) {
  std::vector<std::string> out;
  for (const std::string& l : lines(path)) {
    auto j = nlohmann::ordered_json::parse(l);
    j.erase("timing_ms");
    out.push_back(j.dump());
  }
  return out;
}

std::vector<std::string> imagesIn(const std::string& path) {
  std::vector<std::string> out;
  for (const std::string& l : lines(path)) out.push_back(nlohmann::json::parse(l).at("image"));
  return out;
}

/// A folder of `copies` x 8 frames (symbolic links to the real ones: frames/cNNN/<its name>,
/// the name kept since it dates the frame) and its list file `list.txt`; returns the folder.
std::string archive(const std::string& tag, int copies) {
  const std::string dir = test::makeTempDir(tag);
  fs::create_directory(dir + "/frames");
  std::ofstream list(dir + "/list.txt");
  list << "# frames of the test archive\n\n";
  const auto frames = test::tetra3Frames();
  for (int c = 0; c < copies; ++c) {
    char sub[32];
    std::snprintf(sub, sizeof sub, "frames/c%03d", c);
    fs::create_directories(dir + "/" + sub);
    for (const std::string& f : frames) {
      const std::string name = std::string(sub) + "/" + fs::path(f).filename().string();
      fs::create_symlink(f, dir + "/" + name);
      list << name << "\n";
    }
  }
  return dir;
}

/// `startracker ARGS` started in `dir` as a child of this test (so it can be killed and
/// waited for); returns its pid.
pid_t startCli(const std::string& args, const std::string& dir) {
  const std::string cmd = "cd '" + dir + "' && exec " + test::cliExe() + " " + args +
                          " >stdout.txt 2>stderr.txt </dev/null";
  const pid_t pid = fork();
  if (pid == 0) {
    execl("/bin/sh", "sh", "-c", cmd.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  return pid;
}

/// Waits until `path` holds at least `n` lines (or `pid` ended); true when it does.
bool waitForLines(const std::string& path, std::size_t n, pid_t pid) {
  for (int k = 0; k < 6000; ++k) {
    if (lines(path).size() >= n) return true;
    if (waitpid(pid, nullptr, WNOHANG) == pid) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return false;
}

/// `startracker ARGS` in `dir`, sent `sig` once its results file r.jsonl holds `n` lines.
struct Interrupted {
  bool started = false;  ///< the file reached n lines before the run ended
  int status = 0;        ///< waitpid's
};
Interrupted interruptAfterLines(const std::string& args, const std::string& dir, std::size_t n,
                                int sig) {
  Interrupted r;
  const pid_t pid = startCli(args, dir);
  EXPECT_GT(pid, 0);
  r.started = waitForLines(dir + "/r.jsonl", n, pid);
  kill(pid, sig);
  waitpid(pid, &r.status, 0);
  return r;
}

TEST(SolveAtScale, ShardsMergedAreTheSerialBatchApartFromTimings) {
  const std::string dir = archive("scale_shards", 1);
  const test::CliRun serial = test::runCli(kSolve + "--files-from list.txt -o serial.jsonl", dir);
  ASSERT_EQ(serial.code, 0) << serial.err;
  ASSERT_EQ(lines(dir + "/serial.jsonl").size(), 8u);
  for (int i = 0; i < 3; ++i) {
    const std::string shard = std::to_string(i) + "/3";
    const test::CliRun r = test::runCli(kSolve + "--files-from list.txt --shard " + shard +
                                            " -o parts/part" + std::to_string(i) + ".jsonl",
                                        dir);
    ASSERT_EQ(r.code, 0) << r.err;
    // A summary line per shard: its frames, what became of them, its time.
    EXPECT_THAT(r.err, HasSubstr("shard " + shard + ": " + (i < 2 ? "3" : "2") + " frames"));
    EXPECT_THAT(r.err, HasSubstr("solved, 0 not solved, 0 errors"));
  }
  // Part i holds frames i, i + 3, ...: round-robin over the list.
  const auto frames = test::tetra3Frames();
  auto listed = [&](std::size_t k) { return "frames/c000/" + fs::path(frames[k]).filename().string(); };
  EXPECT_EQ(imagesIn(dir + "/parts/part1.jsonl"),
            (std::vector<std::string>{listed(1), listed(4), listed(7)}));
  const test::CliRun m =
      test::runCli("solve merge parts -o merged.jsonl --files-from list.txt", dir);
  ASSERT_EQ(m.code, 0) << m.err;
  EXPECT_THAT(m.err, HasSubstr("8 frames from 3 parts merged into merged.jsonl"));
  EXPECT_EQ(withoutTimings(dir + "/merged.jsonl"), withoutTimings(dir + "/serial.jsonl"));
  // Timings are the one difference: the comparison sees a changed result.
  std::vector<std::string> other = withoutTimings(dir + "/serial.jsonl");
  other[3].replace(other[3].find("\"ra_deg\":") + 9, 1, "9");
  EXPECT_NE(withoutTimings(dir + "/merged.jsonl"), other);
  // Without the list the order is the frames' names: here the same.
  const test::CliRun by_name = test::runCli(
      "solve merge parts/part2.jsonl parts/part0.jsonl parts/part1.jsonl -o by_name.jsonl", dir);
  ASSERT_EQ(by_name.code, 0) << by_name.err;
  EXPECT_EQ(withoutTimings(dir + "/by_name.jsonl"), withoutTimings(dir + "/serial.jsonl"));
}

TEST(SolveAtScale, ASigkilledRunResumedLosesAndRepeatsNoFrame) {
  const int copies = 60;  // 480 frames: the kill lands while most are still to do
  const std::string dir = archive("scale_kill", copies);
  const Interrupted k =
      interruptAfterLines(kSolve + "--files-from list.txt --threads 2 -o r.jsonl", dir, 20, SIGKILL);
  ASSERT_TRUE(k.started) << test::fileBytes(dir + "/stderr.txt");
  ASSERT_TRUE(WIFSIGNALED(k.status));
  const std::size_t kept = lines(dir + "/r.jsonl").size();
  ASSERT_LT(kept, 8u * copies) << "the run ended before the kill: nothing was tested";

  const test::CliRun resumed =
      test::runCli(kSolve + "--files-from list.txt --threads 2 -o r.jsonl --resume", dir);
  ASSERT_EQ(resumed.code, 0) << resumed.err;
  // Each frame once: the killed run's lines (a cut last one removed) and the resumed run's.
  const std::vector<std::string> got = imagesIn(dir + "/r.jsonl");
  EXPECT_EQ(got.size(), 8u * copies);
  EXPECT_EQ(std::set<std::string>(got.begin(), got.end()).size(), 8u * copies);
  const std::size_t skipped = std::stoul(
      resumed.err.substr(resumed.err.find(" frames, ") + 9));  // "N frames, K with a result"
  EXPECT_GE(skipped + 1, kept);  // at most one line (cut by the kill) solved again
  EXPECT_THAT(resumed.err, HasSubstr("with a result in r.jsonl skipped"));
  // Every line the same result as the serial solve of its frame.
  std::map<std::string, std::string> truth;  // real frame name -> result without image, timing
  const auto frames = test::tetra3Frames();
  for (const std::string& l : lines(dir + "/r.jsonl")) {
    auto j = nlohmann::ordered_json::parse(l);
    const std::string image = j.at("image");
    const std::string real = fs::path(image).filename().string();
    j.erase("image");
    j.erase("timing_ms");
    const auto [it, fresh] = truth.emplace(real, j.dump());
    if (!fresh) {
      EXPECT_EQ(it->second, j.dump()) << image;
    }
  }
  EXPECT_EQ(truth.size(), frames.size());
}

TEST(SolveAtScale, SigtermStopsBetweenFramesAndResumeFinishes) {
  const std::string dir = archive("scale_term", 60);
  const Interrupted t =
      interruptAfterLines(kSolve + "--files-from list.txt -o r.jsonl", dir, 10, SIGTERM);
  ASSERT_TRUE(t.started);
  ASSERT_TRUE(WIFEXITED(t.status));
  EXPECT_EQ(WEXITSTATUS(t.status), 130);
  const std::string err = test::fileBytes(dir + "/stderr.txt");
  EXPECT_THAT(err, HasSubstr("interrupted by SIGTERM after"));
  EXPECT_THAT(err, HasSubstr("--resume continues"));
  // Stopped between frames: every line whole.
  const std::string text = test::fileBytes(dir + "/r.jsonl");
  ASSERT_FALSE(text.empty());
  EXPECT_EQ(text.back(), '\n');
  for (const std::string& l : lines(dir + "/r.jsonl")) EXPECT_NO_THROW(nlohmann::json::parse(l));
  const test::CliRun resumed = test::runCli(kSolve + "--files-from list.txt -o r.jsonl --resume", dir);
  ASSERT_EQ(resumed.code, 0) << resumed.err;
  EXPECT_EQ(lines(dir + "/r.jsonl").size(), 480u);
}

TEST(SolveAtScale, ACutLastLineIsSolvedAgain) {
  const std::string dir = archive("scale_cut", 1);
  ASSERT_EQ(test::runCli(kSolve + "--files-from list.txt -o r.jsonl", dir).code, 0);
  const std::vector<std::string> whole = withoutTimings(dir + "/r.jsonl");
  // The kill's worst case: the last line half written.
  const auto size = fs::file_size(dir + "/r.jsonl");
  fs::resize_file(dir + "/r.jsonl", size - lines(dir + "/r.jsonl").back().size() / 2);
  const test::CliRun merge_cut = test::runCli("solve merge r.jsonl -o m.jsonl", dir);
  EXPECT_EQ(merge_cut.code, 2);
  EXPECT_THAT(merge_cut.err, HasSubstr("its last line is cut"));
  const test::CliRun r = test::runCli(kSolve + "--files-from list.txt -o r.jsonl --resume", dir);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_THAT(r.err, HasSubstr("its last line was cut by the interruption"));
  EXPECT_THAT(r.err, HasSubstr("1 frames, 7 with a result in r.jsonl skipped: 1 solved"));
  EXPECT_EQ(withoutTimings(dir + "/r.jsonl"), whole);
  // A second resume has nothing left to do.
  const test::CliRun again = test::runCli(kSolve + "--files-from list.txt -o r.jsonl --resume", dir);
  EXPECT_EQ(again.code, 0);
  EXPECT_THAT(again.err, HasSubstr("0 frames, 8 with a result"));
  EXPECT_EQ(withoutTimings(dir + "/r.jsonl"), whole);
}

TEST(SolveAtScale, AnUnreadableFrameIsALineAndTheRunSucceeds) {
  const std::string dir = archive("scale_unreadable", 1);
  std::ofstream(dir + "/list.txt", std::ios::app) << "frames/missing.tiff\n";
  // Without -o the exit code is the worst frame's, as before.
  EXPECT_EQ(test::runCli(kSolve + "--files-from list.txt", dir).code, 2);
  const test::CliRun r = test::runCli(kSolve + "--files-from list.txt -o r.jsonl", dir);
  EXPECT_EQ(r.code, 0) << r.err;  // every frame has its line: the run did its work
  EXPECT_THAT(r.err, HasSubstr("9 frames: 8 solved, 0 not solved, 1 errors"));
  const auto last = nlohmann::json::parse(lines(dir + "/r.jsonl").back());
  EXPECT_EQ(last.at("image"), "frames/missing.tiff");
  EXPECT_EQ(last.at("solved"), false);
}

TEST(SolveAtScale, MisusesAreRefusedBeforeAnyWork) {
  const std::string dir = archive("scale_misuse", 1);
  ASSERT_EQ(test::runCli(kSolve + "--files-from list.txt --shard 0/2 -o a.jsonl", dir).code, 0);
  ASSERT_EQ(test::runCli(kSolve + "--files-from list.txt --shard 1/2 -o b.jsonl", dir).code, 0);
  const std::string before = test::fileBytes(dir + "/a.jsonl");
  struct Case {
    std::string args, message;
  };
  const std::vector<Case> cases = {
      {kSolve + "--files-from list.txt --shard 0/2 -o a.jsonl", "--resume continues it"},
      {kSolve + "--files-from list.txt --resume", "--resume continues a results file: give it with -o"},
      {kSolve + "--files-from list.txt --shard 1/2 -o a.jsonl --resume",
       "a frame this run (--shard 1/2) does not solve"},
      {kSolve + "--files-from list.txt --shard 2/2 -o c.jsonl", "--shard '2/2': expected i/N"},
      {kSolve + "--files-from nolist.txt -o c.jsonl", "--files-from nolist.txt: cannot read"},
      {kSolve + "--files-from frames -o c.jsonl", "--files-from frames: a folder"},
      {kSolve + "--files-from list.txt frames/c000/" +
           fs::path(test::tetra3Frames().front()).filename().string() + " -o c.jsonl", "listed twice"},
      {kSolve + "--files-from list.txt -o c.png", "JSON Lines (name it .jsonl)"},
      {kSolve + "--files-from list.txt -o list.txt", "-o"},
      {"solve", "missing IMAGE: PNG, JPEG, TIFF or FITS images, star lists or folders, or --files-from LIST"},
      {"solve merge a.jsonl -o m.jsonl --files-from list.txt", "4 of the list's 8 frames have no result"},
      {"solve merge a.jsonl a.jsonl -o m.jsonl", "has a result in a.jsonl and in a.jsonl"},
      {"solve merge a.jsonl b.jsonl", "give the merged file with -o"},
      {"solve merge a.jsonl b.jsonl -o m.jsonl --fov-deg 11.4", "--fov-deg does not apply"},
      {"solve merge a.jsonl list.txt -o m.jsonl", "list.txt:1: not the result of a frame"},
  };
  for (const Case& c : cases) {
    const test::CliRun r = test::runCli(c.args, dir);
    EXPECT_EQ(r.code, 2) << c.args << "\n" << r.err;
    EXPECT_THAT(r.err, HasSubstr(c.message)) << c.args;
    EXPECT_THAT(r.out, ::testing::Not(HasSubstr("solved"))) << c.args;
  }
  EXPECT_EQ(test::fileBytes(dir + "/a.jsonl"), before);
  EXPECT_FALSE(fs::exists(dir + "/m.jsonl"));
  EXPECT_FALSE(fs::exists(dir + "/c.jsonl"));
  // The two halves merge into the whole.
  const test::CliRun m = test::runCli("solve merge a.jsonl b.jsonl -o m.jsonl --files-from list.txt", dir);
  EXPECT_EQ(m.code, 0) << m.err;
  EXPECT_EQ(lines(dir + "/m.jsonl").size(), 8u);
}

}  // namespace
}  // namespace st

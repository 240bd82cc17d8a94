// Issue 21 item 10 (CLI part): --version on every command; -v/--verbose and -q/--quiet
// before or after the command (common/log.hpp: -q keeps warnings and errors, drops info
// lines and progress bars; -v adds debug lines); OpenCV's own "[ WARN:...]" lines do not
// leak unless -v.
#include <gtest/gtest.h>

#include <fstream>

#include "tests/app/test_cli_run.hpp"

namespace st {
namespace {

using test::runCli;

const char* const kCommands[] = {"camera",     "catalog", "catalog build", "catalog info",
                                 "config",     "dark",    "live",          "montecarlo", "replay",
                                 "simulate",   "solve"};

TEST(CliFlags, VersionOnEveryCommand) {
  const test::CliRun root = runCli("--version");
  ASSERT_EQ(root.code, 0) << root.err;
  ASSERT_EQ(root.out.rfind("startracker ", 0), 0u) << root.out;
  for (const char* cmd : kCommands) {
    const test::CliRun r = runCli(std::string(cmd) + " --version");
    EXPECT_EQ(r.code, 0) << cmd << ": " << r.err;
    EXPECT_EQ(r.out, root.out) << cmd;
  }
}

TEST(CliFlags, VerboseAndQuietAcceptedBeforeAndAfterEveryCommand) {
  // --help last: parsing must accept each flag at either place (one process per pair, the
  // program takes ~0.5 s of CPU to start).
  for (const char* cmd : kCommands)
    for (const std::string& flags : {std::string("-v ") + cmd + " --quiet",
                                     std::string("--quiet ") + cmd + " -v"}) {
      const test::CliRun r = runCli(flags + " --help");
      EXPECT_EQ(r.code, 0) << flags << ": " << r.err;
      EXPECT_NE(r.out.find("-q,--quiet"), std::string::npos) << flags << ": " << r.out;
      EXPECT_NE(r.out.find("-v,--verbose"), std::string::npos) << flags << ": " << r.out;
    }
}

// A small Monte Carlo run speaks on stderr: an info line (the database); its progress bar
// only on a terminal (issue 39; tests/common/test_log.cpp proves the bar on a pseudo-terminal),
// so never into this redirected stderr. -q silences the info wherever it stands; -v adds the
// debug line with the run's options.
TEST(CliFlags, QuietSilencesInfoAndProgressVerboseAddsDebug) {
  const std::string args = "star-count --runs 20 --no-plots --out out";
  const test::CliRun normal = runCli("montecarlo " + args);
  ASSERT_EQ(normal.code, 0) << normal.err;
  EXPECT_EQ(normal.err.find("star-count ["), std::string::npos) << normal.err;  // no bar
  EXPECT_NE(normal.err.find("database:"), std::string::npos) << normal.err;
  EXPECT_EQ(normal.err.find("debug:"), std::string::npos) << normal.err;
  for (const std::string& cmd : {"-q montecarlo " + args, "montecarlo " + args + " -q",
                                 "--quiet montecarlo " + args}) {
    const test::CliRun quiet = runCli(cmd);
    ASSERT_EQ(quiet.code, 0) << cmd << quiet.err;
    EXPECT_EQ(quiet.err, "") << cmd;
    // Results are not chatter: the same tables (the first line holds the run's time).
    auto tables = [](const std::string& out) {
      const auto eol = out.find('\n');
      return eol == std::string::npos ? out : out.substr(eol);
    };
    EXPECT_EQ(tables(quiet.out), tables(normal.out)) << cmd;
  }
  for (const std::string& cmd : {"-v montecarlo " + args, "montecarlo " + args + " --verbose"}) {
    const test::CliRun verbose = runCli(cmd);
    ASSERT_EQ(verbose.code, 0) << cmd << verbose.err;
    EXPECT_NE(verbose.err.find("[montecarlo] debug: startracker montecarlo star-count --runs 20"),
              std::string::npos)
        << cmd << verbose.err;
  }
  // A command's own -q (replay, simulate) also sets the process-wide level, and the
  // root's -q silences their progress bars.
  const std::string scenario = test::repoDir() + "/rawlogs/tour_120s.ini";
  const test::CliRun sim = runCli("-q simulate " + scenario + " --frames 3 -o out/t.rawlog");
  EXPECT_EQ(sim.code, 0) << sim.err;
  EXPECT_EQ(sim.err.find("simulate ["), std::string::npos) << sim.err;
}

// OpenCV prints "[ WARN:0@0.05] global ... imread_('x.png'): can't open/read file" on its
// own for an image it cannot open; the program says it once in its own words, and OpenCV's
// log level is errors only unless -v (app/cli/common_flags.cpp). Missing and undecodable
// images must both give one message of ours and no OpenCV line.
TEST(CliFlags, OpenCvWarningsDoNotLeak) {
  const std::string dir = test::makeTempDir("cli_opencv");
  {
    std::ofstream garbage(dir + "/garbage.png", std::ios::binary);
    garbage << "not a PNG at all, just bytes";
  }
  for (const std::string& image : {dir + "/no_such_image.png", dir + "/garbage.png"}) {
    const test::CliRun r = runCli("solve " + image + " --fov-deg 10");
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_NE(r.err.find(image), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("[ WARN"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("global "), std::string::npos) << r.err;
  }
}

}  // namespace
}  // namespace st

// Issue 21 item 12: CLI parse messages in the project's words. A misspelt command is named
// (CLI11 said "A subcommand is required"); no range bound prints as 309 digits (CLI11's
// NonNegativeNumber); flags are named as the user typed them.
#include <gtest/gtest.h>

#include "tests/app/test_cli_run.hpp"

namespace st {
namespace {

using test::runCli;

void expectUsageError(const std::string& args, const std::string& message) {
  const test::CliRun r = runCli(args);
  EXPECT_EQ(r.code, 2) << args << "\n" << r.err;
  EXPECT_NE(r.err.find(message), std::string::npos) << args << "\n" << r.err;
  EXPECT_FALSE(test::hasLongNumber(r.err)) << args << "\n" << r.err;
  EXPECT_EQ(r.err.find("Run with --help"), std::string::npos) << args << "\n" << r.err;
}

TEST(CliParseErrors, UnknownCommandIsNamedWithTheCommands) {
  expectUsageError("slove x.png",
                   "unknown command 'slove' (did you mean 'solve'?); commands: calibrate, camera, catalog, "
                   "config, dark, live, montecarlo, replay, simulate, solve");
  expectUsageError("catalog biuld", "unknown catalog command 'biuld' (did you mean 'build'?); "
                                    "commands: build, info");
  expectUsageError("", "missing command; commands: calibrate, camera, catalog");
  expectUsageError("frobnicate", "unknown command 'frobnicate'; commands: calibrate, camera");
}

TEST(CliParseErrors, NoThreeHundredDigitBounds) {
  expectUsageError("live live.ini --duration -1", "--duration must be a number >= 0, got -1");
  expectUsageError("catalog build --fov-deg 10 -o x.db --per-region -1",
                   "--per-region -1: must be >= 1, or 0 for no density reduction");
  expectUsageError("camera --fov-deg 500 --size 640 480",
                   "--fov-deg must be a number <= 179, got 500");
  expectUsageError("solve x.png --max-stars 2", "--max-stars must be a whole number from 4 to 100, got 2");
  // Nor in any help text.
  for (const char* cmd : {"camera", "catalog build", "catalog info", "config", "live",
                          "montecarlo", "replay", "simulate", "solve"}) {
    const test::CliRun r = runCli(std::string(cmd) + " --help");
    EXPECT_EQ(r.code, 0) << cmd;
    EXPECT_FALSE(test::hasLongNumber(r.out)) << cmd << "\n" << r.out;
  }
}

TEST(CliParseErrors, FlagsNamedAsTyped) {
  expectUsageError("montecarlo star-count -j -3", "-j must be a whole number >= 0, got -3");
  expectUsageError("montecarlo star-count --threads -3", "--threads must be a whole number >= 0");
  expectUsageError("solve x.png --fov-range 5", "--fov-range takes 2 values, got 1");
  expectUsageError("solve x.png --epoch=abc", "--epoch must be a number from 1000 to 3000, got 'abc'");
  expectUsageError("solve x.png --fov-rnge 5 10",
                   "unknown option '--fov-rnge' (did you mean '--fov-range'?)");
  expectUsageError("solve x.png --algorithm pyramd",
                   "--algorithm must be one of pyramid, voting, liebe, planar, spherical, "
                   "nvertex, nvertex3, nvertex5; got 'pyramd' (did you mean 'pyramid'?)");
  expectUsageError("solve", "missing IMAGE: PNG, JPEG");
  expectUsageError("solve a.png b.png", "b.png: cannot open the image");  // a batch (issue 15)
  expectUsageError("solve x.png --camera c.yaml --fov-deg 10",
                   "--camera and --fov-deg cannot be used together");
}

}  // namespace
}  // namespace st

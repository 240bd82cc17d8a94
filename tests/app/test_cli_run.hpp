/// @file test_cli_run.hpp
/// Runs the startracker binary with stdout and stderr kept apart (test::runCommand merges
/// them), for the tests of the command line's messages and JSON.
#pragma once
#include <cstdlib>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>

#include "tests/support/test_paths.hpp"

namespace st::test {

struct CliRun {
  int code = -1;
  std::string out, err;
};

/// The binary under test; env ST_TEST_STARTRACKER runs the tests against another build
/// (e.g. an older one, to see a new test fail there).
inline std::string cliExe() {
  const char* env = std::getenv("ST_TEST_STARTRACKER");
  return env != nullptr && *env != '\0' ? env : startrackerExe();
}

/// `startracker ARGS` from `dir` (a temp folder by default, so that nothing lands in the
/// repository), with stdin closed; `shell_prefix` runs first in the same shell (a ulimit).
inline CliRun runCli(const std::string& args, const std::string& dir = "",
                     const std::string& shell_prefix = "") {
  const std::string where = dir.empty() ? makeTempDir("cli_run") : dir;
  const std::string out = where + "/stdout.txt", err = where + "/stderr.txt";
  CliRun r;
  // In a subshell: runCommand appends its own 2>&1.
  r.code = runCommand("(cd '" + where + "' && " + shell_prefix + cliExe() + " " + args + " >'" +
                      out + "' 2>'" + err + "' </dev/null)");
  auto slurp = [](const std::string& path) {
    std::ifstream f(path);
    std::stringstream ss;
    ss << f.rdbuf();
    return ss.str();
  };
  r.out = slurp(out);
  r.err = slurp(err);
  return r;
}

/// True when `text` holds a run of more than `n` digits (a 309-digit double bound).
inline bool hasLongNumber(const std::string& text, int n = 20) {
  return std::regex_search(text, std::regex("[0-9]{" + std::to_string(n + 1) + "}"));
}

}  // namespace st::test

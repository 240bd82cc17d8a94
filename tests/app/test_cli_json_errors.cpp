// Issue 21 item 4 (parse-error part): with --json on the command line, a failure that
// reaches main prints ONE JSON object on stdout, {"solved": false, "status": "error", "error":
// "...", "exit_code": N} (solve's own failure object, as the README says: issue 39 found a
// usage error without "solved"/"status"), besides the human message on stderr.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "tests/app/test_cli_run.hpp"

namespace st {
namespace {

using test::runCli;

nlohmann::json expectJsonError(const std::string& args, int code) {
  const test::CliRun r = runCli(args);
  EXPECT_EQ(r.code, code) << args << "\n" << r.err;
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(r.out);  // throws on anything but exactly one JSON value
  } catch (const std::exception& e) {
    ADD_FAILURE() << args << ": stdout is not one JSON object (" << e.what() << "):\n" << r.out;
    return j;
  }
  EXPECT_TRUE(j.is_object()) << r.out;
  EXPECT_TRUE(j.contains("error") && j["error"].is_string()) << r.out;
  EXPECT_EQ(j.value("exit_code", -1), code) << r.out;
  EXPECT_EQ(j.value("solved", true), false) << r.out;
  EXPECT_EQ(j.value("status", ""), "error") << r.out;
  // The human message is still on stderr, with the same text.
  if (j.contains("error") && j["error"].is_string()) {
    EXPECT_NE(r.err.find(j["error"].get<std::string>()), std::string::npos) << r.err;
  }
  return j;
}

TEST(CliJsonErrors, ParseErrorWithJsonPrintsOneJsonObject) {
  const nlohmann::json j = expectJsonError("solve --json --max-stars 2 x.png", 2);
  EXPECT_NE(j.value("error", "").find("--max-stars"), std::string::npos) << j.dump();
  expectJsonError("solve x.png --json --bogus", 2);
  expectJsonError("slove --json x.png", 2);
}

TEST(CliJsonErrors, InputErrorWithJsonPrintsOneJsonObject) {
  // A file name that needs escaping in JSON.
  const nlohmann::json j = expectJsonError(R"(solve --json --fov-deg 10 'no "such\ image.png')", 2);
  EXPECT_NE(j.value("error", "").find(R"(no "such\ image.png)"), std::string::npos) << j.dump();
}

TEST(CliJsonErrors, WithoutJsonStdoutStaysEmpty) {
  const test::CliRun r = runCli("solve --max-stars 2 x.png");
  EXPECT_EQ(r.code, 2);
  EXPECT_EQ(r.out, "");
  // After "--" a "--json" is an argument, not the flag.
  EXPECT_EQ(runCli("config -- --json").out, "");
}

}  // namespace
}  // namespace st

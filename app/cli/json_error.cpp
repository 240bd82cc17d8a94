#include "app/cli/json_error.hpp"

#include <cstdio>

#include "common/log.hpp"
#include "solve/solve_output.hpp"

namespace st::app::cli {

nlohmann::ordered_json errorJson(const std::string& message, int exit_code) {
  // The keys of solve's own failure, as the README states them: a script reads "solved" and
  // "status" whatever failed (issue 39: a usage error lacked them).
  return solve::errorJson(message, exit_code);
}

bool jsonRequested(const std::vector<std::string>& args) {
  for (const std::string& arg : args) {
    if (arg == "--") return false;
    if (arg == "--json") return true;
  }
  return false;
}

int reportFailure(const std::string& message, int exit_code, bool json) {
  log::error("%s", message.c_str());
  if (json) {
    // A message from a file or a value the user gave may hold bytes that are not UTF-8:
    // replace them rather than throw while reporting.
    const std::string text =
        errorJson(message, exit_code).dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace);
    std::printf("%s\n", text.c_str());
    std::fflush(stdout);
  }
  return exit_code;
}

}  // namespace st::app::cli

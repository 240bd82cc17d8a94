/// @file json_error.hpp
/// With `--json` on the command line, a failure that reaches main (a parse error, an
/// st::InputError, a processing failure) prints ONE JSON object on stdout, besides the
/// human message on stderr, so that a script reading stdout always gets JSON:
///   {"error": "--max-stars must be a whole number from 4 to 100, got 2", "exit_code": 2}
/// "error" is the same text as the stderr message; "exit_code" is the process's exit code
/// (2 bad usage or input, 1 processing failure). A command that prints its own result
/// object on a handled failure (solve's {"solved": false, ...}) adds these two keys to it
/// with errorJson() and returns the code instead of throwing, so exactly one object is
/// printed either way.
#pragma once
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace st::app::cli {

/// {"solved": false, "status": "error", "error": message, "exit_code": exit_code}
nlohmann::ordered_json errorJson(const std::string& message, int exit_code);

/// True when `--json` is among `args` (before a `--` that ends the options), whether or not
/// the command line parsed: a script that asked for JSON gets JSON for a parse error too.
bool jsonRequested(const std::vector<std::string>& args);

/// Reports a failure that reached main: st::log::error on stderr, and with `json` the
/// errorJson object on stdout. Returns exit_code.
int reportFailure(const std::string& message, int exit_code, bool json);

}  // namespace st::app::cli

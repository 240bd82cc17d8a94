/// @file common_flags.hpp
/// The flags every command takes, added in one place rather than in each command file:
///   --version        prints "startracker X.Y.Z" and exits 0 (`startracker solve --version`)
///   -v, --verbose    debug lines too, and OpenCV's own warnings
///   -q, --quiet      errors and warnings only: no info lines, no progress bars
/// before or after the command (`startracker -q replay x` = `startracker replay x -q`).
/// -v wins over -q when both are given. The levels are st::log's (common/log.hpp).
/// A command that declares one of these names itself keeps its own (replay's and simulate's
/// -q,--quiet); its count still sets the process-wide level.
#pragma once
#include <CLI/CLI.hpp>
#include <string>

namespace st::app::cli {

/// Adds --version (printing `version_text`), -v/--verbose and -q/--quiet to `root` and to
/// every sub-command under it. Call after every command is added.
void addCommonFlags(CLI::App& root, const std::string& version_text);

/// After a successful parse: sets st::log's verbosity from -v/-q on any parsed level, its tag
/// to the chosen command's name, and OpenCV's log level (errors only; warnings with -v:
/// OpenCV's "[ WARN:0@0.1] global ..." lines name its sources, not the user's input, and
/// the program reports the same failures in its own words).
void applyCommonFlags(const CLI::App& root);

/// `-f,--force` of a command that writes files: without it an existing output is refused
/// (common/output_file.hpp). `help` says more where the command has more to replace.
CLI::Option* addForceFlag(CLI::App& cmd, bool& force,
                          const std::string& help = "Replace existing output files (without it "
                                                    "an existing output is refused)");

}  // namespace st::app::cli

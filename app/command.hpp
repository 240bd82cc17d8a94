/// @file command.hpp
/// How a sub-command plugs into `startracker`: each command file defines one
/// `addXxxCommand(CLI::App&, CommandRun&)` that creates its sub-command and, when it is
/// chosen, sets `run` to the function that does the work. The list of commands lives in
/// one place: app/commands.cpp.
///
/// Exit codes: 0 success, 1 processing failure (returned by `run` or ProcessingError),
/// 2 bad usage or bad input (CLI parse errors and st::InputError).
#pragma once
#include <CLI/CLI.hpp>
#include <functional>

namespace st::app {

constexpr int kExitOk = 0;
constexpr int kExitFailure = 1;
constexpr int kExitUsage = 2;

using CommandRun = std::function<int()>;

/// Registers every sub-command on `root` (defined in commands.cpp).
void addAllCommands(CLI::App& root, CommandRun& run);

}  // namespace st::app

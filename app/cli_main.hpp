/// @file cli_main.hpp
/// One command line for both programs: `startracker-cli` (every command) and
/// `startracker-solve` (solve only, linking no MRPT); the `startracker` launcher picks one.
#pragma once
#include "app/command.hpp"

namespace st::app {

using AddCommands = void (*)(CLI::App& root, CommandRun& run);

/// Parses argv with the commands `add_commands` registers, runs the chosen one and returns
/// the exit code (0 ok, 1 processing failure, 2 usage or input error).
int runCommandLine(int argc, char** argv, AddCommands add_commands);

/// `startracker solve` (app/cmd_solve.cpp).
void addSolveCommand(CLI::App& root, CommandRun& run);

}  // namespace st::app

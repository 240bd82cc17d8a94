/// @file parse_errors.hpp
/// CLI11's parse errors in the project's words. CLI11 says "A subcommand is required" for a
/// misspelt command, prints a double's 309-digit maximum as a range bound, and names a
/// positional by its variable; here the message names what the user typed and what would
/// have been right:
///   unknown command 'slove' (did you mean 'solve'?); commands: camera, catalog, ...
///   --duration must be a number >= 0, got -1
///   --algorithm must be one of pyramid, voting, ...; got 'pyramd' (did you mean 'pyramid'?)
///   missing IMAGE: PNG, JPEG, TIFF (8/16-bit) or FITS image
/// A message this file does not know is passed through unchanged.
#pragma once
#include <CLI/CLI.hpp>
#include <string>
#include <vector>

namespace st::app::cli {

/// The message for a parse error `e` of `root` (after root.parse threw it). `args` are the
/// command-line arguments without the program name, to name options as they were typed.
std::string describeParseError(const CLI::ParseError& e, const CLI::App& root,
                               const std::vector<std::string>& args);

/// The chosen command: the deepest sub-command that was parsed (root when none).
const CLI::App* chosenCommand(const CLI::App& root);

/// "catalog build" for that sub-command of root; "" for root.
std::string commandPath(const CLI::App* app);

}  // namespace st::app::cli

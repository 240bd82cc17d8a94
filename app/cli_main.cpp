// The body of both programs' main (app/main.cpp, app/main_solve.cpp): parse, run the chosen
// command, turn errors into exit codes. What every command shares (flags, number checks,
// parse messages, --json errors) lives in app/cli/.
#include <exception>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include <new>

#include "app/cli/common_flags.hpp"
#include "app/cli/json_error.hpp"
#include "app/cli/parse_errors.hpp"
#include "app/cli/validators.hpp"
#include "app/command.hpp"
#include "common/errors.hpp"
#include "common/log.hpp"
#include "app/cli_main.hpp"

namespace st::app {

int runCommandLine(int argc, char** argv, AddCommands add_commands) {
  CLI::App root{"startracker: star images -> identified stars -> attitude with covariance, "
                "fused with gyro rates.\nRun 'startracker <command> --help' for each command."};
  root.require_subcommand(1);
  root.get_formatter()->label("SUBCOMMAND", "COMMAND");  // shared by every command's help
  CommandRun run;
  add_commands(root, run);
  cli::addCommonFlags(root, std::string("startracker ") + ST_VERSION);
  cli::applyTypeChecks(root);

  const std::vector<std::string> args(argv + 1, argv + argc);
  const bool json = cli::jsonRequested(args);
  try {
    root.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return root.exit(e);  // --help, --version
    const std::string path = cli::commandPath(cli::chosenCommand(root));
    st::log::setTag(path.substr(0, path.find(' ')));
    return cli::reportFailure(cli::describeParseError(e, root, args), kExitUsage, json);
  }
  cli::applyCommonFlags(root);
  try {
    return run ? run() : kExitUsage;
  } catch (const st::InputError& e) {
    return cli::reportFailure(e.what(), kExitUsage, json);
  } catch (const std::bad_alloc&) {
    // Sizes read from files and flags are bounded (issue 39); what is left is the machine's.
    return cli::reportFailure(
        "out of memory: this machine could not give the memory the run needs (free memory, or "
        "split the work: fewer frames per run, a smaller image or catalog)",
        kExitFailure, json);
  } catch (const cv::Exception& e) {
    // OpenCV's own text names its source file and line: the user needs what failed.
    return cli::reportFailure("image processing (OpenCV) failed: " + e.err +
                                  (e.func.empty() ? "" : " in " + e.func),
                              kExitFailure, json);
  } catch (const std::exception& e) {
    return cli::reportFailure(e.what(), kExitFailure, json);
  }
}

}  // namespace st::app

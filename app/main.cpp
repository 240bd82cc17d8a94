// startracker: one program, sub-commands registered in app/commands.cpp.
#include <cstdio>
#include <exception>

#include "app/command.hpp"
#include "common/errors.hpp"

int main(int argc, char** argv) {
  using namespace st::app;
  CLI::App root{"startracker: star images -> identified stars -> attitude with covariance, "
                "fused with gyro rates.\nRun 'startracker <command> --help' for each command."};
  root.set_version_flag("--version", std::string("startracker ") + ST_VERSION);
  root.require_subcommand(1);
  CommandRun run;
  addAllCommands(root, run);
  try {
    root.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = root.exit(e);  // prints help / version / the parse error
    return code == 0 ? kExitOk : kExitUsage;
  }
  try {
    return run ? run() : kExitUsage;
  } catch (const st::InputError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return kExitUsage;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return kExitFailure;
  }
}

// The one list of sub-commands. Adding a command is one file plus one line here.
#include "app/command.hpp"

namespace st::app {

void addCalibrateCommand(CLI::App& root, CommandRun& run);
void addCameraCommand(CLI::App& root, CommandRun& run);
void addCatalogCommand(CLI::App& root, CommandRun& run);
void addConfigCommand(CLI::App& root, CommandRun& run);
void addDarkCommand(CLI::App& root, CommandRun& run);
void addLiveCommand(CLI::App& root, CommandRun& run);
void addMontecarloCommand(CLI::App& root, CommandRun& run);
void addReplayCommand(CLI::App& root, CommandRun& run);
void addSimulateCommand(CLI::App& root, CommandRun& run);
void addSolveCommand(CLI::App& root, CommandRun& run);
void addTestbedCommand(CLI::App& root, CommandRun& run);

void addAllCommands(CLI::App& root, CommandRun& run) {
  addCalibrateCommand(root, run);
  addCameraCommand(root, run);
  addCatalogCommand(root, run);
  addConfigCommand(root, run);
  addDarkCommand(root, run);
  addLiveCommand(root, run);
  addMontecarloCommand(root, run);
  addReplayCommand(root, run);
  addSimulateCommand(root, run);
  addSolveCommand(root, run);
  addTestbedCommand(root, run);
}

}  // namespace st::app

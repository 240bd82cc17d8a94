// `startracker config FILE [--section S]`: the effective configuration of an .ini file,
// every default filled in, in ini form that reads back. The schema is recognised from the
// file's sections (app/config_schemas.cpp); reading is strict, so a misspelled key fails
// here with the nearest valid key, before a long run would have ignored it.
#include <mrpt/config/CConfigFile.h>

#include <cstdio>
#include <filesystem>

#include "app/command.hpp"
#include "app/config_schemas.hpp"
#include "common/errors.hpp"

namespace st::app {

void addConfigCommand(CLI::App& root, CommandRun& run) {
  auto* cmd = root.add_subcommand(
      "config",
      "Check an .ini file strictly and print its effective configuration (every default "
      "filled in; the output reads back). Knows tracker.ini, live .ini files (their own "
      "sections and the sensor sections), scenarios, camera .ini sections and montecarlo run "
      "files");
  struct Opts {
    std::string file, section;
  };
  auto o = std::make_shared<Opts>();
  cmd->add_option("file", o->file, ".ini file")->required();
  cmd->add_option("--section", o->section, "Print only this section (e.g. a camera section)");
  cmd->callback([o, &run] {
    run = [o] {
      if (!std::filesystem::is_regular_file(o->file))
        throw InputError(o->file + ": file does not exist");
      const auto file = openIniFile(o->file);
      const mrpt::config::CConfigFile& cfg = *file;
      SchemaPrinters printers;
      addConfigSchemas(printers);
      const std::string text = printers.print(IniReader{cfg, o->file}, o->section);
      std::printf("# effective configuration of %s\n%s", o->file.c_str(), text.c_str());
      return kExitOk;
    };
  });
}

}  // namespace st::app

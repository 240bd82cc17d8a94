// Every ini schema (config/ and the schemas app/config_schemas.cpp registers: scenario,
// simulated sensors, star tracker sensor, tracker/live .ini, camera sections, Monte Carlo
// run file), read as `startracker config FILE` reads them: strictly, every section.
#include <mrpt/config/CConfigFile.h>

#include "app/config_schemas.hpp"
#include "config/ini_reader.hpp"
#include "tests/fuzz/targets/fuzz_io.hpp"

namespace st::fuzz {

int config_ini(const std::uint8_t* data, std::size_t size) {
  const std::string path = writeInput(data, size, ".ini");
  refuseOnlyWithInputError(path, [&] {
    const auto file = openIniFile(path);
    const mrpt::config::CConfigFile& cfg = *file;
    SchemaPrinters printers;
    app::addConfigSchemas(printers);
    printers.print(IniReader{cfg, path});
  });
  return 0;
}

}  // namespace st::fuzz

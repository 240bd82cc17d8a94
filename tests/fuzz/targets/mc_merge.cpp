// The files `montecarlo merge` reads back (app/montecarlo/): the first byte picks a run file
// (<experiment>_run.txt) or a trials CSV; the rest is the file.
#include "app/montecarlo/csv.hpp"
#include "app/montecarlo/run_file.hpp"
#include "tests/fuzz/targets/fuzz_io.hpp"

namespace st::fuzz {

int mc_merge(const std::uint8_t* data, std::size_t size) {
  const Split in = splitSelector(data, size);
  const bool run_file = in.selector % 2 == 0;
  const std::string path = writeInput(in.data, in.size, run_file ? "_run.txt" : "_trials.csv");
  refuseOnlyWithInputError(path, [&] {
    if (run_file) {
      const app::mc::McRunFile run = app::mc::readRunFile(path);
      app::mc::runFileKeyValues(run);  // what merge compares between shards
    } else {
      app::mc::readCsv(path);
    }
  });
  return 0;
}

}  // namespace st::fuzz

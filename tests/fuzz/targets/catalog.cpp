// Catalog loaders (catalog/): the first byte picks Hipparcos hip_main.dat, Yale BSC5 binary
// or Tycho-2 tyc2.dat; the rest is the file.
#include "catalog/star_catalog.hpp"
#include "tests/fuzz/targets/fuzz_io.hpp"

namespace st::fuzz {

int catalog(const std::uint8_t* data, std::size_t size) {
  const Split in = splitSelector(data, size);
  const std::string path = writeInput(in.data, in.size, ".dat");
  refuseOnlyWithInputError(path, [&] {
    switch (in.selector % 3) {
      case 0: loadHipparcos(path); break;
      case 1: loadBsc5(path); break;
      default: loadTycho2(path); break;
    }
  });
  return 0;
}

}  // namespace st::fuzz

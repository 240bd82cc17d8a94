// Star lists given to `solve` instead of an image (solve/star_list.cpp): the first byte
// picks a CSV or a FITS binary table (solve-field's .xyls); the rest is the file.
#include "solve/star_list.hpp"
#include "tests/fuzz/targets/fuzz_io.hpp"

namespace st::fuzz {

int star_list(const std::uint8_t* data, std::size_t size) {
  const Split in = splitSelector(data, size);
  const std::string path = writeInput(in.data, in.size, in.selector % 2 == 0 ? ".csv" : ".xyls");
  refuseOnlyWithInputError(path, [&] { solve::loadStarList(path); });
  return 0;
}

}  // namespace st::fuzz

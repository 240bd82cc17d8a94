// Star database files (catalog/database_file.cpp). The input is the file without its last 4
// bytes; the target appends their CRC-32, so the fuzzer reaches the parser behind the
// checksum (a bad checksum alone is refused first, and tested in tests/catalog).
#include <zlib.h>

#include <vector>

#include "catalog/star_database.hpp"
#include "tests/fuzz/targets/fuzz_io.hpp"

namespace st::fuzz {

int star_database(const std::uint8_t* data, std::size_t size) {
  std::vector<std::uint8_t> file(data, data + size);
  const auto crc = std::uint32_t(crc32(crc32(0L, Z_NULL, 0), data, uInt(size)));
  for (int i = 0; i < 4; ++i) file.push_back(std::uint8_t(crc >> (8 * i)));  // little-endian
  const std::string path = writeInput(file.data(), file.size(), ".db");
  refuseOnlyWithInputError(path, [&] {
    const StarDatabase db = StarDatabase::load(path);
    // What `catalog info` and the identifier touch first.
    for (const StarPair& p : db.pairs())
      if (p.a >= db.stars().size() || p.b >= db.stars().size()) std::abort();
  });
  return 0;
}

}  // namespace st::fuzz

// loadCatalog: choose the loader from the file's first bytes.
#include <cstdint>
#include <cstring>
#include <fstream>

#include "catalog/star_catalog.hpp"
#include "common/errors.hpp"

namespace st {

StarCatalog loadCatalog(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open catalog file");
  unsigned char h[28] = {};
  in.read(reinterpret_cast<char*>(h), sizeof h);
  if (in.gcount() == std::streamsize(sizeof h)) {
    int32_t star0, star1, nbent;
    std::memcpy(&star0, h, 4);
    std::memcpy(&star1, h + 4, 4);
    std::memcpy(&nbent, h + 24, 4);
    if (star0 == 0 && star1 == 1 && nbent == 32) return loadBsc5(path);
  }
  return loadHipparcos(path);  // plain or gzip text; its own errors name the line
}

}  // namespace st

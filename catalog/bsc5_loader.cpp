// Loader for the Yale Bright Star Catalogue, 5th revised edition, in the binary layout of the
// Harvard TDC distribution (little-endian): a 28-byte header of seven int32 (STAR0, STAR1,
// STARN, STNUM, MPROP, NMAG, NBENT), then |STARN| entries of NBENT = 32 bytes each.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

#include "catalog/star_catalog.hpp"
#include "common/conventions.hpp"
#include "common/errors.hpp"

namespace st {
namespace {

constexpr std::size_t kHeaderBytes = 28;
constexpr std::size_t kEntryBytes = 32;

template <class T>
T readLe(const unsigned char* p) {  // the project only targets little-endian hosts
  static_assert(sizeof(T) <= 8, "scalar");
  T v;
  std::memcpy(&v, p, sizeof(T));
  return v;
}

}  // namespace

StarCatalog loadBsc5(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open BSC5 catalog file");
  const std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(in)),
                                         std::istreambuf_iterator<char>());
  if (bytes.size() < kHeaderBytes)
    throw InputError(path + ": " + std::to_string(bytes.size()) +
                     " bytes, too short for the 28-byte BSC5 header");
  int32_t h[7];
  for (int k = 0; k < 7; ++k) h[k] = readLe<int32_t>(bytes.data() + 4 * k);
  const int32_t star0 = h[0], starn = h[2], stnum = h[3], mprop = h[4], nmag = h[5], nbent = h[6];
  if (star0 != 0 || stnum != 1 || nmag != 1 || mprop != 1 || nbent != int32_t(kEntryBytes) ||
      starn == 0)
    throw InputError(path + ": not a BSC5 binary of the supported layout (header STAR0=" +
                     std::to_string(star0) + " STARN=" + std::to_string(starn) + " STNUM=" +
                     std::to_string(stnum) + " MPROP=" + std::to_string(mprop) + " NMAG=" +
                     std::to_string(nmag) + " NBENT=" + std::to_string(nbent) +
                     "; expected STAR0=0 STNUM=1 MPROP=1 NMAG=1 NBENT=32)");
  if (starn > 0)
    throw InputError(path + ": B1950 positions (STARN > 0) are not supported; use the J2000 file");
  const std::size_t n = std::size_t(-int64_t(starn));
  StarCatalog cat;
  cat.name = "Yale Bright Star Catalogue 5 (Harvard TDC binary)";
  cat.format = "bsc5";
  cat.source_path = path;
  cat.epoch_jyear = 2000.0;
  // n comes from the header: reserve no more than the file can hold (a short file is
  // refused below, naming the record where it ends).
  cat.entries.reserve(std::min(n, (bytes.size() - kHeaderBytes) / kEntryBytes));
  for (std::size_t r = 0; r < n; ++r) {
    const std::size_t off = kHeaderBytes + r * kEntryBytes;
    if (off + kEntryBytes > bytes.size())
      throw InputError(path + ": truncated at record " + std::to_string(r + 1) + " of " +
                       std::to_string(n) + " (file has " + std::to_string(bytes.size()) +
                       " bytes, needs " + std::to_string(kHeaderBytes + n * kEntryBytes) + ")");
    const unsigned char* p = bytes.data() + off;
    const float xno = readLe<float>(p);
    const double ra = readLe<double>(p + 4), dec = readLe<double>(p + 12);
    const int16_t mag100 = readLe<int16_t>(p + 22);
    const float pm_ra = readLe<float>(p + 24), pm_dec = readLe<float>(p + 28);
    if (ra == 0.0 && dec == 0.0) {  // placeholder of a removed nova / non-stellar object
      ++cat.skipped_no_position;
      continue;
    }
    if (!std::isfinite(ra) || !std::isfinite(dec) || ra < 0 || ra > kTwoPi ||
        std::fabs(dec) > kPi / 2 || !(xno >= 1) || !std::isfinite(pm_ra) ||
        !std::isfinite(pm_dec))
      throw InputError(path + ": record " + std::to_string(r + 1) +
                       ": invalid values (HR " + std::to_string(xno) + ", RA " +
                       std::to_string(ra) + " rad, Dec " + std::to_string(dec) + " rad)");
    CatalogEntry e;
    e.id = uint32_t(std::lround(xno));
    e.ra = ra;
    e.dec = dec;
    // XRPM is the RA proper motion already times cos(dec) (checked on Sirius against HIP 32349).
    e.pm_ra_cosdec = pm_ra;
    e.pm_dec = pm_dec;
    e.parallax = 0;
    e.vmag = mag100 / 100.0;
    e.bv = std::numeric_limits<double>::quiet_NaN();
    cat.entries.push_back(e);
  }
  if (bytes.size() > kHeaderBytes + n * kEntryBytes)
    throw InputError(path + ": " + std::to_string(bytes.size() - kHeaderBytes - n * kEntryBytes) +
                     " trailing bytes after the " + std::to_string(n) +
                     " records the header announces");
  cat.completeness_vmag = 6.5;  // Hoffleit & Warren 1991: the stars brighter than about V 6.5
  finishCatalog(cat);
  return cat;
}

}  // namespace st

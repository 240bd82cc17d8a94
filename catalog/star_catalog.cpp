// The catalog format registry (one line per format), format detection, TYC ids, and the
// depth of a catalog with the one warning for a limit beyond it.
#include "catalog/star_catalog.hpp"

#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <set>

#include "common/errors.hpp"

namespace st {
namespace {

struct CatalogFormat {
  const char* name;
  StarCatalog (*load)(const std::string&);
  const char* name_prefix;  ///< file names that start with this are of the format
};

const CatalogFormat kFormats[] = {
    {"hipparcos", &loadHipparcos, "hip_main"},
    {"tycho2", &loadTycho2, "tyc2"},
    {"bsc5", &loadBsc5, "bsc5"},
};

std::string formatList() {
  std::string s;
  for (const CatalogFormat& f : kFormats) s += (s.empty() ? "" : ", ") + std::string(f.name);
  return s;
}

bool isBsc5Header(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  unsigned char h[28] = {};
  in.read(reinterpret_cast<char*>(h), sizeof h);
  if (in.gcount() != std::streamsize(sizeof h)) return false;
  int32_t star0, star1, nbent;
  std::memcpy(&star0, h, 4);
  std::memcpy(&star1, h + 4, 4);
  std::memcpy(&nbent, h + 24, 4);
  return star0 == 0 && star1 == 1 && nbent == 32;
}

// The first line of a plain or gzip text file (empty if none).
std::string firstLine(const std::string& path) {
  gzFile f = gzopen(path.c_str(), "rb");
  if (!f) return {};
  char buf[512] = {};
  const bool ok = gzgets(f, buf, sizeof buf) != nullptr;
  gzclose(f);
  return ok ? std::string(buf) : std::string();
}

// "NNNN NNNNN N|": the TYC field that opens every tyc2.dat record.
bool looksLikeTycho2(const std::string& l) {
  if (l.size() < 13 || l[4] != ' ' || l[10] != ' ' || l[12] != '|') return false;
  for (int k : {0, 1, 2, 3, 5, 6, 7, 8, 9, 11})
    if (l[k] < '0' || l[k] > '9') return false;
  return true;
}

}  // namespace

std::vector<std::string> catalogFormats() {
  std::vector<std::string> v;
  for (const CatalogFormat& f : kFormats) v.push_back(f.name);
  return v;
}

std::string detectCatalogFormat(const std::string& path) {
  if (!std::filesystem::is_regular_file(path))
    throw InputError(path + ": cannot open catalog file (no such file)");
  const std::string base = std::filesystem::path(path).filename().string();
  for (const CatalogFormat& f : kFormats)
    if (base.rfind(f.name_prefix, 0) == 0) return f.name;
  if (isBsc5Header(path)) return "bsc5";
  const std::string l = firstLine(path);
  if (l.rfind("H|", 0) == 0) return "hipparcos";
  if (looksLikeTycho2(l)) return "tycho2";
  throw InputError(path + ": unknown catalog format (neither its name nor its first line is "
                          "one of " + formatList() + "); name it with --catalog-format");
}

StarCatalog loadCatalog(const std::string& path, const std::string& format) {
  const std::string fmt = format == "auto" ? detectCatalogFormat(path) : format;
  for (const CatalogFormat& f : kFormats)
    if (fmt == f.name) return f.load(path);
  throw InputError("catalog format '" + format + "' unknown; known: auto, " + formatList());
}

uint32_t tycho2Id(int tyc1, int tyc2, int tyc3) {
  if (tyc1 < 1 || tyc1 > 9537 || tyc2 < 1 || tyc2 > 12121 || tyc3 < 1 || tyc3 > 7)
    throw InputError("TYC " + std::to_string(tyc1) + "-" + std::to_string(tyc2) + "-" +
                     std::to_string(tyc3) + " is outside the Tycho-2 ranges");
  return (uint32_t(tyc1) << 17) | (uint32_t(tyc2) << 3) | uint32_t(tyc3);
}

std::string tycho2Name(uint32_t id) {
  return "TYC " + std::to_string(id >> 17) + "-" + std::to_string((id >> 3) & 0x3FFF) + "-" +
         std::to_string(id & 7);
}

void finishCatalog(StarCatalog& cat) {
  std::vector<double> v;
  v.reserve(cat.entries.size());
  for (const CatalogEntry& e : cat.entries) v.push_back(e.vmag);
  if (v.empty()) return;
  // 99.9 %: the magnitude-cut subset's one V 9.54 straggler (a variable) does not make it
  // "deep to V 9.5"; for a few dozen entries this is the faintest one.
  const std::size_t k = std::min(v.size() - 1, std::size_t(std::ceil(0.999 * double(v.size()))) - 1);
  std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(k), v.end());
  cat.depth_vmag = v[k];
  cat.faintest_vmag = *std::max_element(v.begin(), v.end());
}

double effectiveMagLimit(const StarCatalog& cat, double mag_limit) {
  if (!(mag_limit > cat.depth_vmag)) return mag_limit;
  static std::mutex mutex;
  static std::set<std::string> warned;  // once per catalog file and process
  std::lock_guard<std::mutex> lock(mutex);
  if (warned.insert(cat.source_path).second)
    std::fprintf(stderr,
                 "[catalog] warning: magnitude limit V %.2f is beyond the depth of %s (V %.2f: "
                 "99.9 %% of its %zu stars are brighter); the database keeps V <= %.2f. "
                 "For fainter stars give a deeper catalog (hip_main.dat, tyc2.dat).\n",
                 mag_limit, cat.source_path.c_str(), cat.depth_vmag, cat.entries.size(),
                 cat.depth_vmag);
  return cat.depth_vmag;
}

}  // namespace st

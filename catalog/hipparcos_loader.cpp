// Loader for the Hipparcos main catalogue in its original `hip_main.dat` format (CDS I/239):
// one star per line, fields separated by '|', counted from 0 for the leading "H".
#include <zlib.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <string>
#include <vector>

#include "catalog/star_catalog.hpp"
#include "common/conventions.hpp"
#include "common/errors.hpp"

namespace st {
namespace {

// Field numbers (from /work/shared/data/README.md and the CDS ReadMe of I/239).
constexpr int kFieldHip = 1, kFieldVmag = 5, kFieldRaDeg = 8, kFieldDeDeg = 9, kFieldPlx = 11,
              kFieldPmRa = 12, kFieldPmDe = 13, kFieldBV = 37;
constexpr int kMinFields = kFieldBV + 1;

std::string trim(const std::string& s, std::size_t b, std::size_t e) {
  while (b < e && (s[b] == ' ' || s[b] == '\t')) ++b;
  while (e > b && (s[e - 1] == ' ' || s[e - 1] == '\t' || s[e - 1] == '\r')) --e;
  return s.substr(b, e - b);
}

struct LineContext {
  const std::string& path;
  std::size_t line;
  std::string where(const char* field) const {
    return path + ":" + std::to_string(line) + ": field " + field;
  }
};

// Empty field -> `empty_value`; anything not a complete number -> InputError.
double parseNumber(const std::string& f, const LineContext& ctx, const char* name,
                   double empty_value) {
  if (f.empty()) return empty_value;
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(f.c_str(), &end);
  if (end == f.c_str() || *end != '\0' || errno == ERANGE || !std::isfinite(v))
    throw InputError(ctx.where(name) + ": '" + f + "' is not a number");
  return v;
}

class GzLineReader {
 public:
  explicit GzLineReader(const std::string& path) : path_(path) {
    f_ = gzopen(path.c_str(), "rb");  // reads plain files transparently
    if (!f_) throw InputError(path + ": cannot open Hipparcos catalog file");
    gzbuffer(f_, 1 << 17);
  }
  ~GzLineReader() {
    if (f_) gzclose(f_);
  }
  GzLineReader(const GzLineReader&) = delete;
  GzLineReader& operator=(const GzLineReader&) = delete;

  /// Next line without the newline; false at the end. Throws on a read error (e.g. a
  /// truncated gzip stream).
  bool next(std::string& line) {
    line.clear();
    char buf[4096];
    while (true) {
      if (!gzgets(f_, buf, sizeof buf)) break;
      line += buf;
      if (!line.empty() && line.back() == '\n') {
        line.pop_back();
        return true;
      }
    }
    int err = Z_OK;
    const char* msg = gzerror(f_, &err);
    if (err != Z_OK && err != Z_STREAM_END)
      throw InputError(path_ + ": read error after line " + std::to_string(lines_) + ": " +
                       (msg ? msg : "unknown zlib error") + " (truncated or corrupt file?)");
    return !line.empty();
  }
  std::size_t lines_ = 0;

 private:
  std::string path_;
  gzFile f_ = nullptr;
};

}  // namespace

StarCatalog loadHipparcos(const std::string& path) {
  StarCatalog cat;
  cat.name = "Hipparcos (ESA 1997, I/239)";
  cat.source_path = path;
  cat.epoch_jyear = 1991.25;
  GzLineReader reader(path);
  std::string line;
  std::vector<std::size_t> bars;
  while (reader.next(line)) {
    const std::size_t lineno = ++reader.lines_;
    if (trim(line, 0, line.size()).empty()) continue;
    const LineContext ctx{path, lineno};
    bars.clear();
    for (std::size_t i = 0; i < line.size(); ++i)
      if (line[i] == '|') bars.push_back(i);
    if (int(bars.size()) < kMinFields - 1)
      throw InputError(path + ":" + std::to_string(lineno) + ": only " +
                       std::to_string(bars.size() + 1) + " '|'-separated fields, need at least " +
                       std::to_string(kMinFields) + " (not a hip_main.dat line, or truncated)");
    auto field = [&](int k) {
      const std::size_t b = k == 0 ? 0 : bars[k - 1] + 1;
      const std::size_t e = k < int(bars.size()) ? bars[k] : line.size();
      return trim(line, b, e);
    };
    if (field(0) != "H")
      throw InputError(ctx.where("0 (catalog letter)") + ": expected 'H', got '" + field(0) + "'");
    const double hip = parseNumber(field(kFieldHip), ctx, "1 (HIP)", -1);
    if (hip < 1 || hip > 4294967295.0 || hip != std::floor(hip))
      throw InputError(ctx.where("1 (HIP)") + ": '" + field(kFieldHip) + "' is not a HIP number");
    const std::string ra_f = field(kFieldRaDeg), de_f = field(kFieldDeDeg);
    if (ra_f.empty() || de_f.empty()) {  // a few entries have no astrometric solution
      ++cat.skipped_no_position;
      continue;
    }
    const double nan = std::numeric_limits<double>::quiet_NaN();
    CatalogEntry e;
    e.id = uint32_t(hip);
    e.ra = deg2rad(parseNumber(ra_f, ctx, "8 (RAdeg)", nan));
    e.dec = deg2rad(parseNumber(de_f, ctx, "9 (DEdeg)", nan));
    if (e.ra < 0 || e.ra > kTwoPi || std::fabs(e.dec) > kPi / 2)
      throw InputError(ctx.where("8/9 (RAdeg/DEdeg)") + ": position out of range");
    e.vmag = parseNumber(field(kFieldVmag), ctx, "5 (Vmag)", nan);
    e.parallax = std::max(0.0, parseNumber(field(kFieldPlx), ctx, "11 (Plx)", 0)) * kRadPerMas;
    e.pm_ra_cosdec = parseNumber(field(kFieldPmRa), ctx, "12 (pmRA)", 0) * kRadPerMas;
    e.pm_dec = parseNumber(field(kFieldPmDe), ctx, "13 (pmDE)", 0) * kRadPerMas;
    e.bv = parseNumber(field(kFieldBV), ctx, "37 (B-V)", nan);
    if (std::isnan(e.vmag)) {
      ++cat.skipped_no_magnitude;
      continue;
    }
    cat.entries.push_back(e);
  }
  if (cat.entries.empty())
    throw InputError(path + ": no star with a position and a V magnitude in the file");
  return cat;
}

}  // namespace st

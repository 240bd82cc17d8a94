// Loader for the Hipparcos main catalogue in its original `hip_main.dat` format (CDS I/239):
// one star per line, fields separated by '|', counted from 0 for the leading "H".
#include <cmath>
#include <limits>
#include <string>

#include "catalog/star_catalog.hpp"
#include "catalog/text_catalog_reader.hpp"
#include "common/conventions.hpp"
#include "common/errors.hpp"

namespace st {
namespace {

// Field numbers (from /work/shared/data/README.md and the CDS ReadMe of I/239).
constexpr int kFieldHip = 1, kFieldVmag = 5, kFieldRaDeg = 8, kFieldDeDeg = 9, kFieldPlx = 11,
              kFieldPmRa = 12, kFieldPmDe = 13, kFieldBV = 37;
/// A hip_main.dat record (CDS I/239) has exactly 78 fields, "H" and H1..H77: fewer is a record
/// cut short (issue 39: a file cut mid-record built a database without a word).
constexpr int kRecordFields = 78;

}  // namespace

StarCatalog loadHipparcos(const std::string& path) {
  using catalog_detail::PipeFields;
  StarCatalog cat;
  cat.name = "Hipparcos (ESA 1997, I/239)";
  cat.format = "hipparcos";
  cat.source_path = path;
  cat.epoch_jyear = 1991.25;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  catalog_detail::forEachPipeRecord(path, "Hipparcos catalog", [&](const PipeFields& f) {
    if (int(f.size()) != kRecordFields)
      throw InputError(f.place() + ": " + std::to_string(f.size()) + " '|'-separated fields where a "
                       "hip_main.dat record has " + std::to_string(kRecordFields) +
                       " (a record cut short: the file is truncated or damaged; or not a "
                       "hip_main.dat line)");
    if (f[0] != "H")
      throw InputError(f.where("0 (catalog letter)") + ": expected 'H', got '" + f[0] + "'");
    const double hip = f.number(kFieldHip, "1 (HIP)", -1);
    if (hip < 1 || hip > 4294967295.0 || hip != std::floor(hip))
      throw InputError(f.where("1 (HIP)") + ": '" + f[kFieldHip] + "' is not a HIP number");
    if (f[kFieldRaDeg].empty() || f[kFieldDeDeg].empty()) {  // no astrometric solution
      ++cat.skipped_no_position;
      return;
    }
    CatalogEntry e;
    e.id = uint32_t(hip);
    e.ra = deg2rad(f.number(kFieldRaDeg, "8 (RAdeg)", nan));
    e.dec = deg2rad(f.number(kFieldDeDeg, "9 (DEdeg)", nan));
    if (e.ra < 0 || e.ra > kTwoPi || std::fabs(e.dec) > kPi / 2)
      throw InputError(f.where("8/9 (RAdeg/DEdeg)") + ": position out of range");
    e.vmag = f.number(kFieldVmag, "5 (Vmag)", nan);
    e.parallax = std::max(0.0, f.number(kFieldPlx, "11 (Plx)", 0)) * kRadPerMas;
    e.pm_ra_cosdec = f.number(kFieldPmRa, "12 (pmRA)", 0) * kRadPerMas;
    e.pm_dec = f.number(kFieldPmDe, "13 (pmDE)", 0) * kRadPerMas;
    e.bv = f.number(kFieldBV, "37 (B-V)", nan);
    if (std::isnan(e.vmag)) {
      ++cat.skipped_no_magnitude;
      return;
    }
    cat.entries.push_back(e);
  });
  if (cat.entries.empty())
    throw InputError(path + ": no star with a position and a V magnitude in the file");
  cat.completeness_vmag = 7.3;  // ESA 1997 vol. 1 sec. 1.2: complete to V 7.3-9 (by latitude, colour)
  finishCatalog(cat);
  return cat;
}

}  // namespace st

// Loader for the Tycho-2 main catalogue `tyc2.dat` (CDS I/259 catalog.dat): one star per
// 206-byte record, 32 fields separated by '|' (the TYC triple is one field, HIP + CCDM one).
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "catalog/star_catalog.hpp"
#include "catalog/text_catalog_reader.hpp"
#include "common/conventions.hpp"
#include "common/errors.hpp"

namespace st {
namespace {

// Field numbers, counted from 0 (I/259 ReadMe, "Byte-by-byte description of file: catalog.dat").
constexpr int kFieldTyc = 0, kFieldPflag = 1, kFieldMRa = 2, kFieldMDe = 3, kFieldPmRa = 4,
              kFieldPmDe = 5, kFieldBT = 17, kFieldVT = 19, kFieldRa = 24, kFieldDe = 25;
constexpr int kFields = 32;

}  // namespace

StarCatalog loadTycho2(const std::string& path) {
  using catalog_detail::PipeFields;
  StarCatalog cat;
  cat.name = "Tycho-2 (Hog et al. 2000, I/259)";
  cat.format = "tycho2";
  cat.source_path = path;
  cat.epoch_jyear = 2000.0;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  catalog_detail::forEachPipeRecord(path, "Tycho-2 catalog", [&](const PipeFields& f) {
    if (int(f.size()) != kFields)
      throw InputError(f.place() + ": " + std::to_string(f.size()) +
                       " '|'-separated fields, a tyc2.dat record has " + std::to_string(kFields) +
                       " (not a tyc2.dat line, or truncated)");
    int t1 = 0, t2 = 0, t3 = 0;
    char rest = 0;
    if (std::sscanf(f[kFieldTyc].c_str(), "%d %d %d %c", &t1, &t2, &t3, &rest) != 3)
      throw InputError(f.where("0 (TYC1 TYC2 TYC3)") + ": '" + f[kFieldTyc] +
                       "' is not a TYC identifier");
    CatalogEntry e;
    try {
      e.id = tycho2Id(t1, t2, t3);
    } catch (const InputError& err) {
      throw InputError(f.where("0 (TYC1 TYC2 TYC3)") + ": " + err.what());
    }
    const bool mean = f[kFieldPflag] != "X";
    const int ra_k = mean ? kFieldMRa : kFieldRa, de_k = mean ? kFieldMDe : kFieldDe;
    const char* ra_name = mean ? "2 (mRAdeg)" : "24 (RAdeg)";
    if (f[ra_k].empty() || f[de_k].empty()) {
      ++cat.skipped_no_position;
      return;
    }
    e.ra = deg2rad(f.number(ra_k, ra_name, nan));
    e.dec = deg2rad(f.number(de_k, mean ? "3 (mDEdeg)" : "25 (DEdeg)", nan));
    if (e.ra < 0 || e.ra > kTwoPi || std::fabs(e.dec) > kPi / 2)
      throw InputError(f.where(ra_name) + ": position out of range");
    // Without a mean position there is no proper motion; the observed position (epoch
    // ~1991) then stands for J2000 (about 1 % of the entries, mostly faint doubles).
    e.pm_ra_cosdec = mean ? f.number(kFieldPmRa, "4 (pmRA)", 0) * kRadPerMas : 0;
    e.pm_dec = mean ? f.number(kFieldPmDe, "5 (pmDE)", 0) * kRadPerMas : 0;
    e.parallax = 0;
    const double bt = f.number(kFieldBT, "17 (BTmag)", nan);
    const double vt = f.number(kFieldVT, "19 (VTmag)", nan);
    if (std::isnan(vt)) {
      ++cat.skipped_no_magnitude;
      return;
    }
    e.vmag = std::isnan(bt) ? vt : vt - 0.090 * (bt - vt);
    e.bv = std::isnan(bt) ? nan : 0.850 * (bt - vt);
    cat.entries.push_back(e);
  });
  if (cat.entries.empty())
    throw InputError(path + ": no star with a position and a VT magnitude in the file");
  cat.completeness_vmag = 11.0;  // Hog et al. 2000: 99 % complete to V 11.0, 90 % to 11.5
  finishCatalog(cat);
  return cat;
}

}  // namespace st

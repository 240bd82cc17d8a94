/// @file star_catalog.hpp
/// Star catalogs as read from disk: the Hipparcos main catalogue (`hip_main.dat`, plain or
/// gzip, a subset or the full 118,218 stars), Tycho-2 (`tyc2.dat`, plain or gzip, 2.5 million
/// stars) and the Yale Bright Star Catalogue 5 (Harvard TDC binary). Positions are ICRS at the
/// catalog's own epoch; epoch corrections live in catalog/epoch_correction.hpp.
///
/// Star ids: a Hipparcos entry's id is its HIP number, a BSC5 entry's its HR number, and a
/// Tycho-2 entry's its TYC1-TYC2-TYC3 triple packed into 32 bits by tycho2Id() (always
/// >= 2^17 = 131072, above every HIP number, so the two never collide).
///
/// Depth: every loader records `depth_vmag`, the magnitude to which the file holds its stars
/// (99.9 % of its entries are at least that bright; a few stragglers of a magnitude-cut subset
/// do not count). A database built with a fainter limit gets no more stars: StarDatabase::build
/// uses min(limit, depth), records both and warns once (effectiveMagLimit()).
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace st {

struct CatalogEntry {
  uint32_t id;          ///< HIP number, HR number or packed TYC (see the file comment)
  double ra, dec;       ///< [rad] ICRS at the catalog epoch
  double pm_ra_cosdec;  ///< [rad/yr] proper motion in RA, already times cos(dec)
  double pm_dec;        ///< [rad/yr]
  double parallax;      ///< [rad], 0 when unknown
  double vmag;          ///< V magnitude (Tycho-2: from BT, VT, see loadTycho2)
  double bv;            ///< B-V colour, NaN when unknown
};

struct StarCatalog {
  std::string name, source_path;
  std::string format;  ///< registry name of the loader: "hipparcos", "tycho2", "bsc5"
  double epoch_jyear;  ///< epoch of the positions (1991.25 Hipparcos, 2000.0 BSC5, Tycho-2)
  std::vector<CatalogEntry> entries;
  std::size_t skipped_no_position = 0;  ///< entries without a position (not in `entries`)
  std::size_t skipped_no_magnitude = 0;  ///< entries with a position but no V (not in `entries`)
  /// [mag] 99.9 % of the entries have V <= depth_vmag (set by finishCatalog()).
  double depth_vmag = 0;
  double faintest_vmag = 0;  ///< [mag] the faintest entry
  /// [mag] the completeness its authors state for the full catalogue (Hipparcos 7.3, Tycho-2
  /// 11.0 at 99 %, BSC5 6.5), for information; a subset is complete to min(this, depth).
  double completeness_vmag = 0;
};

/// Hipparcos `hip_main.dat` format (pipe-separated, CDS I/239), plain or gzip (by content,
/// not by name). Reads the full 118,218-star file as well as subsets. Throws InputError naming
/// the file and line on a malformed line or a file that cannot be read.
StarCatalog loadHipparcos(const std::string& path);

/// Tycho-2 main catalogue `tyc2.dat` (CDS I/259 `catalog.dat`, '|'-separated, 32 fields),
/// plain or gzip; the 20 distributed pieces `tyc2.dat.NN.gz` concatenated
/// (`cat tyc2.dat.*.gz > tyc2.dat.gz`) read as one file. Positions: the mean position at
/// J2000 (mRAdeg/mDEdeg) with its proper motion; an entry without one (pflag X) gets its
/// observed position (RAdeg/DEdeg, epoch ~1991) and zero proper motion. V = VT - 0.090 (BT - VT)
/// and B-V = 0.850 (BT - VT) (ESA 1997 vol. 1 sec. 1.3 app. 4); VT alone gives V = VT; an entry
/// without VT is skipped and counted. The supplements (suppl_1.dat, which holds the brightest
/// stars, e.g. Sirius) are not read. No parallax (0). InputError names file, line and field.
StarCatalog loadTycho2(const std::string& path);

/// Yale BSC5 binary (Harvard TDC layout, little-endian: 28-byte header, 32-byte entries,
/// J2000 positions). Throws InputError naming the file and record on a bad header or a
/// truncated file. Zero-position placeholders are skipped and counted.
StarCatalog loadBsc5(const std::string& path);

/// The catalog formats loadCatalog() knows, one line each in star_catalog.cpp.
std::vector<std::string> catalogFormats();

/// Loads `path` in `format` (one of catalogFormats(), or "auto"). "auto" picks the format from
/// the file name (tyc2* -> tycho2, hip_main* -> hipparcos, bsc5* -> bsc5), else from the content
/// (a BSC5 header, a line starting "H|", a "NNNN NNNNN N|" TYC field). InputError names the
/// file, or the format and the known ones.
StarCatalog loadCatalog(const std::string& path, const std::string& format = "auto");

/// The format "auto" picks for `path` (see loadCatalog); InputError when none fits.
std::string detectCatalogFormat(const std::string& path);

/// Packs a TYC identifier: (tyc1 << 17) | (tyc2 << 3) | tyc3, for tyc1 in [1, 9537],
/// tyc2 in [1, 12121], tyc3 in [1, 7] (Tycho-2 uses 1-4); InputError outside.
uint32_t tycho2Id(int tyc1, int tyc2, int tyc3);
/// "TYC 1472-1436-2" for a packed id.
std::string tycho2Name(uint32_t id);

/// Sets depth_vmag and faintest_vmag from the entries (every loader calls it last).
void finishCatalog(StarCatalog& cat);

/// min(limit, cat.depth_vmag). A limit beyond the depth warns once per process and catalog
/// file on stderr, naming the file, its depth and the limit.
double effectiveMagLimit(const StarCatalog& cat, double mag_limit);

}  // namespace st

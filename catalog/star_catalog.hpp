/// @file star_catalog.hpp
/// Star catalogs as read from disk: the Hipparcos main catalogue (`hip_main.dat`, plain or
/// gzip) and the Yale Bright Star Catalogue 5 (Harvard TDC binary). Positions are ICRS at the
/// catalog's own epoch; epoch corrections live in catalog/epoch_correction.hpp.
#pragma once
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace st {

struct CatalogEntry {
  uint32_t id;          ///< HIP number (Hipparcos) or HR number (BSC5)
  double ra, dec;       ///< [rad] ICRS at the catalog epoch
  double pm_ra_cosdec;  ///< [rad/yr] proper motion in RA, already times cos(dec)
  double pm_dec;        ///< [rad/yr]
  double parallax;      ///< [rad], 0 when unknown
  double vmag;          ///< V magnitude
  double bv;            ///< B-V colour, NaN when unknown
};

struct StarCatalog {
  std::string name, source_path;
  double epoch_jyear;  ///< epoch of the positions (1991.25 Hipparcos, 2000.0 BSC5)
  std::vector<CatalogEntry> entries;
  std::size_t skipped_no_position = 0;  ///< entries without a position (not in `entries`)
  std::size_t skipped_no_magnitude = 0;  ///< entries with a position but no V (not in `entries`)
};

/// Hipparcos `hip_main.dat` format (pipe-separated, CDS I/239), plain or gzip (by content,
/// not by name). Reads the full 118,218-star file as well as subsets. Throws InputError naming
/// the file and line on a malformed line or a file that cannot be read.
StarCatalog loadHipparcos(const std::string& path);

/// Yale BSC5 binary (Harvard TDC layout, little-endian: 28-byte header, 32-byte entries,
/// J2000 positions). Throws InputError naming the file and record on a bad header or a
/// truncated file. Zero-position placeholders are skipped and counted.
StarCatalog loadBsc5(const std::string& path);

/// Picks the loader from the file content: a BSC5 header (STAR0=0, STAR1=1, NBENT=32) or
/// else the Hipparcos text format.
StarCatalog loadCatalog(const std::string& path);

}  // namespace st

/// @file catalog_fixture.hpp
/// Shared, lazily built databases for the catalog tests (built once per test program).
#pragma once
#include "catalog/star_database.hpp"

namespace st::test {

/// The committed Hipparcos subset (loaded once).
const StarCatalog& hipSubset();
/// Parameters of the reference database: 15 deg pairs, V <= 6.5, epoch 2020.0, 10 arcsec
/// double-star merge, neighbours within 5 deg.
DatabaseParams params15();
/// The reference database built from hipSubset() with params15().
const StarDatabase& hipDatabase15();

}  // namespace st::test

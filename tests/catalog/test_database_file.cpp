// The database file: round trip, and refusal of corrupt / other-version / foreign files.
#include <gtest/gtest.h>
#include <zlib.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "catalog/star_database.hpp"
#include "common/errors.hpp"
#include "tests/catalog/catalog_fixture.hpp"
#include "tests/support/test_paths.hpp"

namespace st {
namespace {

std::string readBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}
void writeBytes(const std::string& path, const std::string& b) {
  std::ofstream(path, std::ios::binary).write(b.data(), std::streamsize(b.size()));
}
std::string loadError(const std::string& path) {
  try {
    StarDatabase::load(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(StarDatabaseFile, RoundTripIsExact) {
  const StarDatabase& db = test::hipDatabase15();
  const std::string path = test::makeTempDir("catalog") + "/db.stdb";
  db.save(path);
  const auto bytes = std::filesystem::file_size(path);
  std::printf("[ info ] database file %.2f MB (%zu stars, %zu pairs)\n", bytes / 1e6,
              db.stars().size(), db.pairs().size());
  EXPECT_LT(bytes, 10u * 1000 * 1000);
  const StarDatabase back = StarDatabase::load(path);
  ASSERT_EQ(back.stars().size(), db.stars().size());
  for (std::size_t i = 0; i < db.stars().size(); ++i) {
    ASSERT_EQ(back.stars()[i].id, db.stars()[i].id);
    ASSERT_EQ(back.stars()[i].u_i, db.stars()[i].u_i);
    ASSERT_EQ(back.stars()[i].mag, db.stars()[i].mag);
  }
  ASSERT_EQ(back.pairs().size(), db.pairs().size());
  ASSERT_EQ(0, std::memcmp(back.pairs().data(), db.pairs().data(),
                           db.pairs().size() * sizeof(StarPair)));
  EXPECT_EQ(back.pairKVector().table(), db.pairKVector().table());
  for (uint32_t i = 0; i < db.stars().size(); ++i)
    ASSERT_TRUE(std::equal(db.neighboursBegin(i), db.neighboursEnd(i), back.neighboursBegin(i),
                           back.neighboursEnd(i)));
  EXPECT_EQ(back.params().max_pair_angle, db.params().max_pair_angle);
  EXPECT_EQ(back.params().mag_limit, db.params().mag_limit);
  EXPECT_EQ(back.params().epoch_jyear, db.params().epoch_jyear);
  EXPECT_EQ(back.params().aberration, db.params().aberration);
  EXPECT_EQ(back.params().double_star_sep, db.params().double_star_sep);
  EXPECT_EQ(back.params().neighbour_radius, db.params().neighbour_radius);
  EXPECT_EQ(back.report().catalog_name, db.report().catalog_name);
  EXPECT_EQ(back.report().catalog_epoch_jyear, 1991.25);
  EXPECT_EQ(back.report().after_mag_limit, db.report().after_mag_limit);
  EXPECT_EQ(back.report().catalog_path, StarDatabase::defaultCatalogPath());
  EXPECT_EQ(back.report().catalog_depth_vmag, db.report().catalog_depth_vmag);
  EXPECT_EQ(back.report().requested_mag_limit, db.report().requested_mag_limit);
  std::vector<uint32_t> a, b;
  db.coneQuery(db.stars()[5].u_i, 0.1, a);
  back.coneQuery(db.stars()[5].u_i, 0.1, b);
  EXPECT_EQ(a, b);
  ASSERT_GT(db.screenStars().size(), 0u);
  ASSERT_EQ(back.screenStars().size(), db.screenStars().size());
  for (std::size_t i = 0; i < db.screenStars().size(); ++i) {
    ASSERT_EQ(back.screenStars()[i].u_i, db.screenStars()[i].u_i);
    ASSERT_EQ(back.screenStars()[i].mag, db.screenStars()[i].mag);
  }
  db.screenConeQuery(db.stars()[5].u_i, 0.1, a);
  back.screenConeQuery(db.stars()[5].u_i, 0.1, b);
  EXPECT_EQ(a, b);
}

TEST(StarDatabaseFile, RefusesCorruptOtherVersionAndForeignFiles) {
  const std::string dir = test::makeTempDir("catalog");
  const std::string good = dir + "/good.stdb";
  test::hipDatabase15().save(good);
  const std::string bytes = readBytes(good);
  EXPECT_EQ(loadError(good), "");  // the intact file loads (the checks below have teeth)

  std::string flipped = bytes;
  flipped[bytes.size() / 2] ^= 0x10;
  writeBytes(dir + "/flip.stdb", flipped);
  EXPECT_NE(loadError(dir + "/flip.stdb").find("checksum"), std::string::npos);

  writeBytes(dir + "/cut.stdb", bytes.substr(0, bytes.size() - 1000));
  EXPECT_NE(loadError(dir + "/cut.stdb").find("cut.stdb"), std::string::npos);

  // A newer format version, with a checksum that is right for the changed bytes.
  std::string newer = bytes.substr(0, bytes.size() - 4);
  const uint32_t version = StarDatabase::kFileFormat + 1;
  std::memcpy(&newer[8], &version, 4);
  const uint32_t crc = uint32_t(crc32(0, reinterpret_cast<const Bytef*>(newer.data()), uInt(newer.size())));
  newer.append(reinterpret_cast<const char*>(&crc), 4);
  writeBytes(dir + "/newer.stdb", newer);
  const std::string msg = loadError(dir + "/newer.stdb");
  EXPECT_NE(msg.find("version " + std::to_string(version)), std::string::npos) << msg;
  EXPECT_NE(msg.find("newer.stdb"), std::string::npos) << msg;

  writeBytes(dir + "/foreign.stdb", "hello, not a database at all........");
  EXPECT_NE(loadError(dir + "/foreign.stdb").find("bad magic"), std::string::npos);
  EXPECT_NE(loadError(dir + "/missing.stdb").find("cannot open"), std::string::npos);
}

// A file of format 2 (before the blend-screen stars) still loads, with an empty screen.
TEST(StarDatabaseFile, ReadsFormat2FilesWithoutAScreen) {
  const std::string dir = test::makeTempDir("catalog");
  const StarDatabase& db = test::hipDatabase15();
  ASSERT_GT(db.screenStars().size(), 0u);
  db.save(dir + "/v2.stdb", 2);
  const StarDatabase back = StarDatabase::load(dir + "/v2.stdb");
  EXPECT_EQ(back.stars().size(), db.stars().size());
  EXPECT_EQ(back.pairs().size(), db.pairs().size());
  EXPECT_TRUE(back.screenStars().empty());
  std::vector<uint32_t> near;
  back.screenConeQuery(db.stars()[0].u_i, 0.5, near);
  EXPECT_TRUE(near.empty());
}

// A file of format 3 (before the B-V colours) loads with unknown colours; format 4 keeps
// the catalog's B-V of every star (photometry's colour term reads no catalog).
TEST(StarDatabaseFile, FormatFourKeepsColoursAndThreeReadsWithout) {
  const std::string dir = test::makeTempDir("catalog");
  const StarDatabase& db = test::hipDatabase15();
  db.save(dir + "/v4.stdb");
  db.save(dir + "/v3.stdb", 3);
  const StarDatabase v4 = StarDatabase::load(dir + "/v4.stdb");
  const StarDatabase v3 = StarDatabase::load(dir + "/v3.stdb");
  ASSERT_EQ(v4.stars().size(), db.stars().size());
  std::size_t coloured = 0;
  for (std::size_t i = 0; i < db.stars().size(); ++i) {
    const float a = db.stars()[i].bv, b = v4.stars()[i].bv;
    EXPECT_TRUE((std::isnan(a) && std::isnan(b)) || a == b) << i;
    coloured += std::isfinite(a);
    EXPECT_TRUE(std::isnan(v3.stars()[i].bv)) << i;
  }
  EXPECT_GT(coloured, db.stars().size() * 9 / 10);  // Hipparcos gives B-V for almost all
  EXPECT_EQ(v3.screenStars().size(), db.screenStars().size());
  EXPECT_THROW(db.save(dir + "/v9.stdb", 9), InputError);
}

// A file of format 1 (before the catalog's depth was recorded), built by the program of
// commit de0cfd1 from tests/data/catalogs/hip_main_sample.dat (--fov-deg 20 --mag-limit 6.5
// --epoch 2020), still loads: the requested limit is the recorded one, the depth unknown.
TEST(StarDatabaseFile, ReadsFormat1Files) {
  const std::string path = test::repoDir() + "/tests/data/catalogs/stars_format1.db";
  const StarDatabase db = StarDatabase::load(path);
  EXPECT_EQ(db.stars().size(), 32u);
  EXPECT_EQ(db.pairs().size(), 26u);
  EXPECT_EQ(db.params().mag_limit, 6.5);
  EXPECT_EQ(db.params().epoch_jyear, 2020.0);
  EXPECT_EQ(db.report().requested_mag_limit, 6.5);
  EXPECT_TRUE(std::isnan(db.report().catalog_depth_vmag));
  EXPECT_EQ(db.report().catalog_path, "");
  EXPECT_EQ(db.report().catalog_name, "Hipparcos (ESA 1997, I/239)");
}

}  // namespace
}  // namespace st

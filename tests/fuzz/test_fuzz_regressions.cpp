// Issue 18: the reproducers of fuzz findings (tests/fuzz/regressions/<target>/, kept once
// fixed) run through their fuzz target exactly as the fuzzer ran them; a crash, a sanitizer
// report or an exception other than InputError there is the finding back. The named tests
// below feed each reproducer to its parser and check the refusal's words.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <zlib.h>

#include "sensors/mrpt/camera_ini.hpp"
#include "catalog/star_catalog.hpp"
#include "catalog/star_database.hpp"
#include "common/errors.hpp"
#include "config/ini_reader.hpp"
#include "sensors/camera/camera_model.hpp"
#include "tests/app/test_cli_run.hpp"
#include "tests/fuzz/targets/fuzz_io.hpp"
#include "tests/support/test_paths.hpp"

namespace st {
namespace {

namespace fs = std::filesystem;

struct Entry {
  const char* name;
  fuzz::Target fn;
};
const Entry kTargets[] = {
#define ST_FUZZ_TARGET(name) {#name, &fuzz::name},
#include "tests/fuzz/target_list.inc"
#undef ST_FUZZ_TARGET
};

std::string readBytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

TEST(FuzzRegressions, EveryReproducerRunsCleanThroughItsTarget) {
  int ran = 0;
  for (const Entry& t : kTargets) {
    const fs::path dir = fs::path(ST_FUZZ_REGRESSIONS_DIR) / t.name;
    if (!fs::is_directory(dir)) continue;
    for (const auto& f : fs::directory_iterator(dir)) {
      SCOPED_TRACE(f.path().string());
      const std::string bytes = readBytes(f.path());
      EXPECT_EQ(t.fn(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()), 0);
      ++ran;
    }
  }
  // A folder without a target (renamed target) would silently test nothing.
  for (const auto& d : fs::directory_iterator(ST_FUZZ_REGRESSIONS_DIR)) {
    bool known = false;
    for (const Entry& t : kTargets) known |= d.path().filename() == t.name;
    EXPECT_TRUE(!d.is_directory() || known) << d.path() << ": no fuzz target of that name";
  }
  RecordProperty("reproducers", ran);
}

fs::path reproducer(const std::string& target, const std::string& name) {
  return fs::path(ST_FUZZ_REGRESSIONS_DIR) / target / name;
}

/// Copies `bytes` to a fresh file named `name` and returns its path.
std::string writeFile(const std::string& name, const std::string& bytes) {
  const std::string path = test::makeTempDir("fuzz_regressions") + "/" + name;
  std::ofstream(path, std::ios::binary) << bytes;
  return path;
}

/// Expects `parse` to throw InputError naming `path` and saying `words`.
template <class F>
void expectRefused(const std::string& path, const std::string& words, F&& parse) {
  try {
    parse();
    ADD_FAILURE() << path << ": accepted";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(path), std::string::npos) << what;
    EXPECT_NE(what.find(words), std::string::npos) << what;
  }
}

// A star database (valid checksum) whose neighbour table claims 2^31 entries: the loader
// allocated 2.2 GB for them before finding the file too short.
TEST(FuzzRegressions, StarDatabaseNeighbourCountBeyondTheFileIsRefusedBeforeAllocating) {
  std::string bytes = readBytes(reproducer("star_database", "neighbour_count_oom"));
  const auto crc = std::uint32_t(crc32(crc32(0L, Z_NULL, 0),
                                       reinterpret_cast<const Bytef*>(bytes.data()), uInt(bytes.size())));
  for (int i = 0; i < 4; ++i) bytes += char(crc >> (8 * i));  // as the fuzz target does
  const std::string path = writeFile("neighbours.db", bytes);
  expectRefused(path, "truncated or corrupt while reading neighbours", [&] { StarDatabase::load(path); });
}

// A 260-byte BSC5 file whose header announces 16.8 million records: the loader reserved
// 1.2 GB for them (12 s under ASan) before finding the file too short.
TEST(FuzzRegressions, Bsc5RecordCountBeyondTheFileIsRefusedNamingTheRecord) {
  const std::string bytes = readBytes(reproducer("catalog", "bsc5_record_count_slow"));
  const std::string path = writeFile("bsc5", bytes.substr(1));  // byte 0: the target's selector
  expectRefused(path, "record ", [&] { loadBsc5(path); });
}

// A camera .ini with an unclosed `$env{`: MRPT's preprocessor threw its own exception out of
// the CConfigFile constructor (`startracker config` exited 1 printing MRPT's call stack).
TEST(FuzzRegressions, IniWithBadPreprocessorSyntaxIsAnInputErrorNamingTheFile) {
  const std::string bytes = readBytes(reproducer("camera", "ini_env_unclosed"));
  const std::string path = writeFile("camera.ini", bytes.substr(1));  // byte 0: the selector
  expectRefused(path, "Expected closing", [&] { loadCameraIniFile(path, "camera"); });
  expectRefused(path, "not a readable .ini file", [&] { openIniFile(path); });
  // What a user saw: exit 1 and MRPT's banner and call stack.
  const test::CliRun r = test::runCli("config '" + path + "'");
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find(path + ": not a readable .ini file"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("Call stack"), std::string::npos) << r.err;
}

// An OpenCV YAML camera file whose camera_matrix declares a huge size: OpenCV's reader
// allocated and zeroed it (> 20 s under ASan, a fuzz timeout) before the 3x3 check.
TEST(FuzzRegressions, CameraYamlWithAHugeDeclaredMatrixIsRefusedBeforeReadingIt) {
  const std::string bytes = readBytes(reproducer("camera", "yaml_huge_matrix_timeout"));
  const std::string path = writeFile("camera.yaml", bytes.substr(1));  // byte 0: the selector
  expectRefused(path, "matrix (at most 16 values)", [&] { CameraModel::loadYaml(path); });
}

// A YAML camera file with NUL bytes in it: OpenCV 4.6's YAML parser never returned (checked
// outside the fuzzer too: 20 s and counting without sanitizers). Refused before OpenCV.
TEST(FuzzRegressions, CameraYamlWithANulByteIsRefusedBeforeOpenCvLoopsOnIt) {
  const std::string bytes = readBytes(reproducer("camera", "yaml_nul_byte_endless_loop"));
  const std::string path = writeFile("camera.yaml", bytes.substr(1));  // byte 0: the selector
  expectRefused(path, "a NUL byte at offset 34", [&] { CameraModel::loadYaml(path); });
}

// A YAML camera file with a single-'!' tag ("!pe-") on a line after an indented key: OpenCV
// 4.6's YAML parser never returned (minimal form "%YAML:1.0\n s:6\n!pe-\n", checked outside the
// fuzzer). Refused before OpenCV; OpenCV's own "!!opencv-matrix" tags still read (every camera
// test file has them).
TEST(FuzzRegressions, CameraYamlWithASingleBangTagIsRefusedBeforeOpenCvLoopsOnIt) {
  const std::string bytes = readBytes(reproducer("camera", "yaml_single_bang_tag_endless_loop"));
  const std::string path = writeFile("camera.yaml", bytes.substr(1));  // byte 0: the selector
  expectRefused(path, "a YAML tag with a single '!'", [&] { CameraModel::loadYaml(path); });
  const std::string minimal = writeFile("minimal.yaml", "%YAML:1.0\n s:6\n!pe-\n");
  expectRefused(minimal, "a YAML tag with a single '!' at offset 15",
                [&] { CameraModel::loadYaml(minimal); });
}

}  // namespace
}  // namespace st

namespace st {
namespace {

// A damaged inline JPEG image in a rawlog's CImage: MRPT decodes it with libjpeg's default
// error manager, whose error_exit called exit(1) after one line of libjpeg's ("Not a JPEG
// file: starts with 0x00 0x00"): replay ended with no word of the file or object. With
// sensors/mrpt/jpeg_errors.hpp the failure is an exception, reported as damage: exit 2 here
// (object 0, nothing readable before it), naming the file and the object.
TEST(FuzzRegressions, DamagedInlineJpegIsReportedAsDamageNotExit) {
  const std::string path = writeFile(
      "jpeg.rawlog", readBytes(reproducer("rawlog", "cimage_jpeg_libjpeg_exit")));
  const test::CliRun r = test::runCli("replay '" + path + "'");
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("rawlog '" + path + "', object 0"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("truncated or not a rawlog"), std::string::npos) << r.err;
}

// A rawlog object that is an MRPT matrix declaring gigabytes of elements: MRPT's aligned
// allocator did not check aligned_alloc's NULL and std::vector zero-filled through it (SIGSEGV,
// exit 139); now the allocation throws (sensors/mrpt/mrpt_allocation.hpp) and replay reports
// damage at object 0 with exit 2.
TEST(FuzzRegressions, MatrixOfDeclaredGigabytesIsReportedAsDamageNotSegfault) {
  const std::string path = writeFile(
      "matrix.rawlog", readBytes(reproducer("rawlog", "cmatrixd_declared_size_segv")));
  const test::CliRun r = test::runCli("replay '" + path + "'");
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("rawlog '" + path + "', object 0"), std::string::npos) << r.err;
  // Refused by the read budget before MRPT's allocator (issue 39), in words, not "bad_alloc".
  EXPECT_NE(r.err.find("declares more memory than this 53-byte file can describe"),
            std::string::npos)
      << r.err;
}

}  // namespace
}  // namespace st

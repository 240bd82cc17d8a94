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

#include "tests/fuzz/targets/fuzz_io.hpp"

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

}  // namespace
}  // namespace st

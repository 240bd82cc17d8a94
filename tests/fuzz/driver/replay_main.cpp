// st_fuzz_replay TARGET PATH...: runs a fuzz target once on every file under each PATH (a
// file or a folder; a missing folder is skipped), as the fuzzer would, without libFuzzer.
// The default (gcc) build runs it on the seed corpora and past findings (ctest label fuzz).
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "tests/fuzz/targets/fuzz_io.hpp"

namespace {

struct Entry {
  const char* name;
  st::fuzz::Target fn;
};
const Entry kTargets[] = {
#define ST_FUZZ_TARGET(name) {#name, &st::fuzz::name},
#include "tests/fuzz/target_list.inc"
#undef ST_FUZZ_TARGET
};

int runFile(st::fuzz::Target fn, const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  const std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  fn(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size());
  return 1;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: st_fuzz_replay TARGET [FILE|DIR]...\n");
    return 2;
  }
  const std::string want = argv[1];
  st::fuzz::Target fn = nullptr;
  for (const Entry& e : kTargets)
    if (want == e.name) fn = e.fn;
  if (!fn) {
    std::fprintf(stderr, "st_fuzz_replay: no fuzz target '%s'\n", want.c_str());
    return 2;
  }
  int n = 0;
  for (int i = 2; i < argc; ++i) {
    const std::filesystem::path p = argv[i];
    if (std::filesystem::is_directory(p)) {
      for (const auto& f : std::filesystem::recursive_directory_iterator(p))
        if (f.is_regular_file()) n += runFile(fn, f.path());
    } else if (std::filesystem::is_regular_file(p)) {
      n += runFile(fn, p);
    }
  }
  std::printf("st_fuzz_replay %s: %d inputs, no finding\n", want.c_str(), n);
  return n > 0 ? 0 : 1;
}

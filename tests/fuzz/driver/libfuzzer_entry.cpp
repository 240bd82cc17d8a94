// libFuzzer's entry point for one target, chosen at compile time (-DST_FUZZ_ENTRY=name).
#include "tests/fuzz/targets/fuzz_io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return st::fuzz::ST_FUZZ_ENTRY(data, size);
}

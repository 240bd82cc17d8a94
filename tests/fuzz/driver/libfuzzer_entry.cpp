// libFuzzer's entry point for one target, chosen at compile time (-DST_FUZZ_ENTRY=name).
#include "tests/fuzz/targets/fuzz_io.hpp"

// Around each input: a target's executable may link driver/allocation_cap.cpp, which limits
// the allocations the input itself causes (libFuzzer's own are not limited).
extern "C" __attribute__((weak)) void stFuzzInputBegins() {}
extern "C" __attribute__((weak)) void stFuzzInputEnds() {}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  stFuzzInputBegins();
  const int rc = st::fuzz::ST_FUZZ_ENTRY(data, size);
  stFuzzInputEnds();
  return rc;
}

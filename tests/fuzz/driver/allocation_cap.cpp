// Linked into fuzz_rawlog only (libFuzzer build): while an input is processed
// (libfuzzer_entry.cpp), the global operator new throws std::bad_alloc for a request above
// 16 MB, as it does on a machine without that memory. libFuzzer's own allocations, outside
// the input, are not limited.
//
// Why: MRPT 2.5 reads a string by resizing it to the length stored in the file before reading
// a byte of it (tests/fuzz/upstream_mrpt/: a damaged CObservationImage's TCamera asks for up
// to 4 GB). That is MRPT's, below anything this project reads, and not fixable here; replay
// already turns the failure into "damaged at object N" (sensors/mrpt/rawlog_io.cpp catches
// std::exception, bad_alloc included). Under ASan the same request aborts the fuzzer as an
// out-of-memory after a few hundred inputs, so no rawlog campaign could get further. With the
// cap, the request fails the way it fails in production, every other check (ASan through
// malloc/free, UBSan, the harness' contract) stays, and the upstream finding keeps its
// reproducers. The fuzzer's inputs are at most 6 KB (the seed corpus' largest file sets
// libFuzzer's -max_len): a request above 16 MB can only come from a length read out of
// damaged bytes, and zero-filling such requests was 80 % of the campaign's time (perf), 60
// inputs per second instead of thousands.
#include <atomic>
#include <cstdlib>
#include <new>

namespace {
constexpr std::size_t kCap = std::size_t(16) << 20;
std::atomic<bool> g_in_input{false};

bool overCap(std::size_t n) { return n > kCap && g_in_input.load(std::memory_order_relaxed); }

void* capped(std::size_t n) {
  if (overCap(n)) throw std::bad_alloc();
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
}  // namespace

extern "C" void stFuzzInputBegins() { g_in_input = true; }
extern "C" void stFuzzInputEnds() { g_in_input = false; }

void* operator new(std::size_t n) { return capped(n); }
void* operator new[](std::size_t n) { return capped(n); }
void* operator new(std::size_t n, const std::nothrow_t&) noexcept {
  return overCap(n) ? nullptr : std::malloc(n ? n : 1);
}
void* operator new[](std::size_t n, const std::nothrow_t&) noexcept {
  return overCap(n) ? nullptr : std::malloc(n ? n : 1);
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { std::free(p); }

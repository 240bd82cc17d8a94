/// @file mrpt_allocation.hpp
/// MRPT's aligned allocations that fail throw std::bad_alloc. MRPT 2.5's allocator for its
/// matrices and aligned vectors (mrpt/core/aligned_allocator.h) uses `mrpt::aligned_malloc`,
/// i.e. aligned_alloc(), without checking the result: a damaged rawlog object whose matrix
/// declares gigabytes (CMatrixD::serializeFrom resizes before reading) had std::vector
/// zero-fill through a null pointer, and `replay` died of SIGSEGV (fuzz finding 2026-12-03,
/// tests/fuzz/regressions/rawlog/cmatrixd_declared_size_segv). This project defines
/// `mrpt::aligned_malloc` as MRPT does (aligned_alloc of the size rounded up to the alignment,
/// freed by MRPT's aligned_free = free) but throwing when the allocation fails or the rounding
/// would overflow; the dynamic linker resolves MRPT's calls to the executable's definition
/// first, and the rawlog reader reports the bad_alloc as damage like any other failed read.
///
/// Every object read from a rawlog runs under a ReadAllocationBudget: the thread's
/// operator new allocations while it lives are counted and fail with std::bad_alloc (read
/// as damage) once they pass what the file can describe, so a damaged length field costs a
/// failed read instead of gigabytes touched (issue 39: a 355-byte rawlog made replay touch
/// 1.66 GB; others asked for 12.9, 22.5 and 72.6 GB).
#pragma once
#include <cstddef>
#include <cstdint>

namespace st {

/// What reading one object from a rawlog of `file_bytes` bytes may allocate: deflate expands
/// at most 1032:1, so the file holds at most 1032 x its size of object bytes; four times that
/// (vectors grow by doubling, MRPT copies what it reads) plus 8 MB for MRPT's own bookkeeping,
/// and never more than kMaxRawlogObjectBytes.
std::size_t rawlogReadBudget(std::uint64_t file_bytes);
/// 1 GiB: no object a star tracker records is larger (an inline 2^28-pixel 16-bit image is 512 MB).
constexpr std::size_t kMaxRawlogObjectBytes = std::size_t(1) << 30;

/// False in sanitizer builds, whose own operator new is kept (mrpt_allocation.cpp).
bool rawlogReadBudgetEnforced();

/// While alive, the calling thread's operator new allocations are summed and fail once the sum
/// passes `bytes`. Not nested.
class ReadAllocationBudget {
 public:
  explicit ReadAllocationBudget(std::size_t bytes);
  ~ReadAllocationBudget();
  ReadAllocationBudget(const ReadAllocationBudget&) = delete;
  ReadAllocationBudget& operator=(const ReadAllocationBudget&) = delete;
};

/// True; referencing it keeps the definition linked into every program that reads rawlogs
/// (RawlogReader calls it).
bool mrptAllocationsThrow();

}  // namespace st

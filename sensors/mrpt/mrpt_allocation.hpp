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
#pragma once

namespace st {

/// True; referencing it keeps the definition linked into every program that reads rawlogs
/// (RawlogReader calls it).
bool mrptAllocationsThrow();

}  // namespace st

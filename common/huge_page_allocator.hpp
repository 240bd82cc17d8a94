/// @file huge_page_allocator.hpp
/// A std::allocator for the few big arrays a process loads at start (the star database's
/// pairs, k-vector and neighbour table: 10, 3.5 and 1.7 MB for a 12 deg camera): blocks from
/// 1 MB up are 2 MB-aligned, rounded up to 2 MB and advised as transparent huge pages
/// (MADV_HUGEPAGE; Debian's default THP mode is "madvise"), so first touching them costs one
/// page fault per 2 MB instead of one per 4 KB. A plate solve per process touches
/// its database once: on the VM measured here a 4 KB fault costs ~20 us, 2,700 of them
/// ~55 ms. Smaller blocks are plain operator new. Where THP is off the advice is ignored.
#pragma once
#include <sys/mman.h>

#include <cstddef>
#include <cstdlib>
#include <new>

namespace st {

template <class T>
struct HugePageAllocator {
  using value_type = T;
  static constexpr std::size_t kHugePage = std::size_t(2) << 20;
  static constexpr std::size_t kMinBytes = std::size_t(1) << 20;  ///< smaller: operator new

  HugePageAllocator() = default;
  template <class U>
  HugePageAllocator(const HugePageAllocator<U>&) noexcept {}

  T* allocate(std::size_t n) {
    if (n > std::size_t(-1) / sizeof(T)) throw std::bad_array_new_length();
    const std::size_t bytes = n * sizeof(T);
    if (bytes < kMinBytes) return static_cast<T*>(::operator new(bytes));
    const std::size_t rounded = (bytes + kHugePage - 1) / kHugePage * kHugePage;
    void* p = std::aligned_alloc(kHugePage, rounded);
    if (!p) throw std::bad_alloc();
    ::madvise(p, rounded, MADV_HUGEPAGE);  // advice only: ignored where THP is off
    return static_cast<T*>(p);
  }
  void deallocate(T* p, std::size_t n) noexcept {
    if (n * sizeof(T) < kMinBytes)
      ::operator delete(p);
    else
      std::free(p);
  }
  template <class U>
  bool operator==(const HugePageAllocator<U>&) const noexcept { return true; }
  template <class U>
  bool operator!=(const HugePageAllocator<U>&) const noexcept { return false; }
};

}  // namespace st

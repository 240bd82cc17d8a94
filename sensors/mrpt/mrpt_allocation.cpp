#include "sensors/mrpt/mrpt_allocation.hpp"

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <new>

namespace mrpt {

void* aligned_malloc(std::size_t size, std::size_t alignment);

void* aligned_malloc(std::size_t size, std::size_t alignment) {
  if (alignment != 0 && size % alignment != 0) {
    if (size > SIZE_MAX - alignment) throw std::bad_alloc();
    size = (size / alignment + 1) * alignment;
  }
  void* p = std::aligned_alloc(alignment, size);
  if (p == nullptr && size != 0) throw std::bad_alloc();
  return p;
}

}  // namespace mrpt

namespace st {

namespace {
struct Budget {
  bool active = false;
  std::size_t left = 0;
};
thread_local Budget t_budget;

[[maybe_unused]] void* counted(std::size_t size, std::size_t alignment) {
  if (t_budget.active) {
    if (size > t_budget.left) throw std::bad_alloc();
    t_budget.left -= size;
  }
  if (size == 0) size = 1;
  void* p = nullptr;
  if (alignment <= alignof(std::max_align_t)) {
    p = std::malloc(size);
  } else {
    if (size > SIZE_MAX - alignment) throw std::bad_alloc();
    p = std::aligned_alloc(alignment, (size + alignment - 1) / alignment * alignment);
  }
  if (p == nullptr) throw std::bad_alloc();
  return p;
}
}  // namespace

bool mrptAllocationsThrow() { return true; }

std::size_t rawlogReadBudget(std::uint64_t file_bytes) {
  const std::uint64_t describable = file_bytes * 1032u;
  const std::uint64_t budget = 4 * describable + (std::uint64_t(8) << 20);
  return budget > kMaxRawlogObjectBytes ? kMaxRawlogObjectBytes : static_cast<std::size_t>(budget);
}

ReadAllocationBudget::ReadAllocationBudget(std::size_t bytes) {
  t_budget.active = true;
  t_budget.left = bytes;
}

ReadAllocationBudget::~ReadAllocationBudget() { t_budget.active = false; }

}  // namespace st

// The program's operator new (the replaceable global allocation functions): malloc as
// libstdc++'s own, freed by its operator delete (free), plus the budget above. Defined in this
// file, which every program reading rawlogs links (mrptAllocationsThrow). Not in sanitizer
// builds: ASan and TSan bring their own operator new (and ASan would see our malloc freed by
// its operator delete as a mismatch); there the fuzzers' allocation limits stand in.
#if !defined(__SANITIZE_ADDRESS__) && !defined(__SANITIZE_THREAD__)
bool st::rawlogReadBudgetEnforced() { return true; }
void* operator new(std::size_t size) { return st::counted(size, 0); }
void* operator new[](std::size_t size) { return st::counted(size, 0); }
void* operator new(std::size_t size, std::align_val_t al) {
  return st::counted(size, static_cast<std::size_t>(al));
}
void* operator new[](std::size_t size, std::align_val_t al) {
  return st::counted(size, static_cast<std::size_t>(al));
}
#else
bool st::rawlogReadBudgetEnforced() { return false; }
#endif

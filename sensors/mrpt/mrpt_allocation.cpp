#include "sensors/mrpt/mrpt_allocation.hpp"

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

bool mrptAllocationsThrow() { return true; }

}  // namespace st

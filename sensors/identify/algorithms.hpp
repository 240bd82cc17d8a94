/// @file algorithms.hpp
/// What the identification algorithms share (internal to sensors/identify/). Their factories
/// are declared by the registry table itself (registry.cpp), one line per algorithm.
#pragma once
#include <memory>

#include "sensors/identify/identifier.hpp"

namespace st::identify_detail {

/// Mortari's index pattern for choosing triangles (i, j, k) among n stars: varies the
/// spacing first so that one bad star (a spike) does not stall the search on it.
template <class F>
void forEachTriangle(int n, F&& f) {
  for (int dj = 1; dj <= n - 2; ++dj)
    for (int dk = 1; dk <= n - dj - 1; ++dk)
      for (int i = 0; i + dj + dk < n; ++i)
        if (f(i, i + dj, i + dj + dk)) return;
}

}  // namespace st::identify_detail

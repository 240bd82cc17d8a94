/// @file algorithms.hpp
/// What the identification algorithms share (internal to sensors/identify/). Their factories
/// are declared by the registry table itself (registry.cpp), one line per algorithm.
#pragma once
#include <memory>

#include "sensors/identify/identifier.hpp"
#include "sensors/identify/search_context.hpp"

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

/// Catalog triangles (a, b, c) shaped like the observed triangle (i, j, k): (a, b) from the
/// i-j k-vector slice in both orders, c a partner of a in the i-k slice, side b-c checked
/// directly, mirror images rejected. Counts the i-j pairs as attitudes examined and uses
/// ctx.lists(0). Calls f(a, b, c) until it returns true; returns whether it did.
template <class F>
bool forEachCatalogTriangle(SearchContext& ctx, int i, int j, int k, F&& f) {
  const PairSlice sij = ctx.slice(i, j);
  ctx.addAttitudes(2.0 * sij.size());
  PartnerLists& lik = ctx.lists(0);
  lik.build(ctx.slice(i, k));
  bool stop = false;
  for (const StarPair* p = sij.begin; p != sij.end && !stop; ++p)
    for (int o = 0; o < 2 && !stop; ++o) {
      const uint32_t a = o ? p->b : p->a, b = o ? p->a : p->b;
      lik.forEach(a, [&](uint32_t c) {
        if (!stop && c != b && ctx.angleMatches(j, k, b, c) &&
            ctx.sameHandedness(i, j, k, a, b, c))
          stop = f(a, b, c);
      });
    }
  return stop;
}

}  // namespace st::identify_detail

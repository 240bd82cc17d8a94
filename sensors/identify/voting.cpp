// Mortari's reference-star matching (seed 000, "Reference-star" section): for a reference
// observation r, the k-vector slices of all pairs (r, k) are pooled into the index vector
// M_r; the true catalog index of r appears once per true companion star. The seed's rules:
//  - n_x (empty slices) > n_smax = floor(n/4) -> r is a spike or the data too noisy, next r;
//  - f1 (top count) must reach the number of companions allowed by the spike bound
//    ((n-1) - n_smax; the seed writes f1 > 3n/4 - 1) and f2 < 1 + int(n/5) marks an
//    unambiguous reference; with a dense catalog f2 is often larger by chance, so ambiguous
//    references are not discarded but their top candidates are verified in count order;
//  - companion k is star l_k when l1 appears exactly once in M_{r,k} (eq. 15).
// Two departures, on purpose (docs/montecarlo/seed000.md, "The reference-star rules"): n - 2
// references are tried where the seed aborts after n - 3, and f1 >= (n-1) - n_smax is one
// lower than the seed's f1 > 3n/4 - 1 when 4 divides n, where the seed's f1 would refuse the
// very spikes its n_smax admits.
#include <algorithm>

#include "sensors/identify/algorithms.hpp"
#include "sensors/identify/search_context.hpp"

namespace st {
namespace {

class VotingIdentifier final : public StarIdentifier {
 public:
  explicit VotingIdentifier(const IdentifyOptions& o) : StarIdentifier(o) {}
  std::string name() const override { return "voting"; }

 private:
  void doIdentify(SearchContext& ctx) const override {
    const int n = ctx.n;
    const int n_smax = n / 4;
    const uint32_t f_needed = static_cast<uint32_t>(std::max(2, (n - 1) - n_smax));
    std::vector<PairSlice> slices(n);
    std::vector<std::pair<uint32_t, uint32_t>> top;  // (count, star)
    std::vector<StarMatch> seeds;
    for (int r = 0; r + 3 <= n && !ctx.done(); ++r) {
      StarCounter& hist = ctx.counter(0);
      hist.clear();
      int n_x = 0;
      top.clear();
      for (int k = 0; k < n; ++k) {
        if (k == r) continue;
        slices[k] = ctx.slice(r, k);
        ctx.addAttitudes(2.0 * slices[k].size());
        if (slices[k].size() == 0) ++n_x;
        for (const StarPair* p = slices[k].begin; p != slices[k].end; ++p)
          for (uint32_t s : {p->a, p->b}) {
            if (hist.tag(s) == static_cast<uint32_t>(k)) continue;  // once per slice
            hist.setTag(s, k);
            if (hist.add(s) == f_needed) top.push_back({0, s});
          }
      }
      if (n_x > n_smax || top.empty()) continue;
      for (auto& t : top) t.first = hist.get(t.second);
      std::sort(top.begin(), top.end(), std::greater<>());
      if (top.size() > 4) top.resize(4);
      for (const auto& [f1, l1] : top) {
        seeds.clear();
        seeds.push_back({static_cast<uint32_t>(r), l1, 0, 0, 0});
        for (int k = 0; k < n; ++k) {
          if (k == r) continue;
          int found = 0;
          uint32_t partner = 0;
          for (const StarPair* p = slices[k].begin; p != slices[k].end; ++p) {
            if (p->a == l1) ++found, partner = p->b;
            else if (p->b == l1) ++found, partner = p->a;
          }
          if (found == 1) seeds.push_back({static_cast<uint32_t>(k), partner, 0, 0, 0});
        }
        if (seeds.size() < 3) continue;
        if (ctx.tryHypothesis(seeds) || ctx.done()) return;
      }
    }
  }
};

}  // namespace

// The factory the registry table (registry.cpp) names.
namespace identify_detail {
std::unique_ptr<StarIdentifier> makeVoting(const IdentifyOptions& o) {
  return std::make_unique<VotingIdentifier>(o);
}
}  // namespace identify_detail

}  // namespace st

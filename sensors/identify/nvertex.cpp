// n-vertex match with n = 4 (seed 004 sec. 5.5.4, eq. 6.7): the six baselines of four
// observed stars A, B, C, D are looked up at once; a candidate for A must appear in the
// slices of baselines AB, AC and AD (the S-matrix "self-consistency"), and the remaining
// baselines BC, BD, CD must hold between the assigned candidates. Every consistent
// 4-vertex assignment is verified.
#include "sensors/identify/algorithms.hpp"
#include "sensors/identify/search_context.hpp"

namespace st {
namespace {

class NVertexIdentifier final : public StarIdentifier {
 public:
  explicit NVertexIdentifier(const IdentifyOptions& o) : StarIdentifier(o) {}
  std::string name() const override { return "nvertex"; }

 private:
  bool tryQuad(SearchContext& ctx, int i, int j, int k, int l,
               std::vector<StarMatch>& seeds) const {
    const PairSlice sij = ctx.slice(i, j);
    ctx.addAttitudes(2.0 * sij.size());
    PartnerLists &lik = ctx.lists(0), &lil = ctx.lists(1);
    lik.build(ctx.slice(i, k));
    lil.build(ctx.slice(i, l));
    for (const StarPair* p = sij.begin; p != sij.end; ++p)
      for (int o = 0; o < 2; ++o) {
        const uint32_t a = o ? p->b : p->a, b = o ? p->a : p->b;
        if (!lik.has(a) || !lil.has(a)) continue;  // A must be in columns AB, AC and AD
        bool stop = false;
        lik.forEach(a, [&](uint32_t c) {
          if (stop || c == b || !ctx.angleMatches(j, k, b, c) ||
              !ctx.sameHandedness(i, j, k, a, b, c))
            return;
          lil.forEach(a, [&](uint32_t d) {
            if (stop || d == b || d == c || !ctx.angleMatches(j, l, b, d) ||
                !ctx.angleMatches(k, l, c, d))
              return;
            const int oi[4] = {i, j, k, l};
            const uint32_t si[4] = {a, b, c, d};
            for (int q = 0; q < 4; ++q) seeds[q] = {static_cast<uint32_t>(oi[q]), si[q], 0, 0, 0};
            stop = ctx.tryHypothesis(seeds) || ctx.done();
          });
        });
        if (stop) return true;
      }
    return false;
  }

  void doIdentify(SearchContext& ctx) const override {
    std::vector<StarMatch> seeds(4);
    const int n = ctx.n;
    // Spread the choice like Mortari's pattern: spacing first, then position.
    for (int dj = 1; dj <= n - 3; ++dj)
      for (int dk = 1; dk <= n - dj - 2; ++dk)
        for (int dl = 1; dl <= n - dj - dk - 1; ++dl)
          for (int i = 0; i + dj + dk + dl < n; ++i) {
            if (ctx.done()) return;
            if (tryQuad(ctx, i, i + dj, i + dj + dk, i + dj + dk + dl, seeds)) return;
          }
  }
};

}  // namespace

// The factory the registry table (registry.cpp) names.
namespace identify_detail {
std::unique_ptr<StarIdentifier> makeNVertex(const IdentifyOptions& o) {
  return std::make_unique<NVertexIdentifier>(o);
}
}  // namespace identify_detail

}  // namespace st

// Mortari's Pyramid (seed 002 ref. [18], seed 004 sec. 5.5.4): a triangle of observed stars
// is matched through three k-vector lookups, then confirmed by a fourth star whose three
// angles to the triangle must match too; every confirmed pyramid is verified.
#include <array>

#include "sensors/identify/algorithms.hpp"
#include "sensors/identify/search_context.hpp"

namespace st {
namespace {

class PyramidIdentifier final : public StarIdentifier {
 public:
  explicit PyramidIdentifier(const IdentifyOptions& o) : StarIdentifier(o) {}
  std::string name() const override { return "pyramid"; }

 private:
  void doIdentify(SearchContext& ctx) const override {
    std::vector<std::array<uint32_t, 3>> tris;
    std::vector<StarMatch> seeds(4);
    identify_detail::forEachTriangle(ctx.n, [&](int i, int j, int k) {
      if (ctx.done()) return true;
      tris.clear();
      identify_detail::forEachCatalogTriangle(ctx, i, j, k,
                                              [&](uint32_t a, uint32_t b, uint32_t c) {
                                                tris.push_back({a, b, c});
                                                return false;  // all of them
                                              });
      if (tris.empty()) return false;
      // Confirm with a 4th star r: a catalog star d at the right angles from a, b and c.
      PartnerLists& lir = ctx.lists(1);
      for (int r = 0; r < ctx.n; ++r) {
        if (r == i || r == j || r == k) continue;
        lir.build(ctx.slice(i, r));
        for (const auto& t : tris) {
          bool stop = false;
          lir.forEach(t[0], [&](uint32_t d) {
            if (stop || d == t[1] || d == t[2] || !ctx.angleMatches(j, r, t[1], d) ||
                !ctx.angleMatches(k, r, t[2], d))
              return;
            const int oi[4] = {i, j, k, r};
            const uint32_t si[4] = {t[0], t[1], t[2], d};
            for (int q = 0; q < 4; ++q) {
              seeds[q].obs_index = oi[q];
              seeds[q].star_index = si[q];
            }
            stop = ctx.tryHypothesis(seeds) || ctx.done();
          });
          if (stop) return true;
        }
      }
      return false;
    });
  }
};

}  // namespace

// The factory the registry table (registry.cpp) names.
namespace identify_detail {
std::unique_ptr<StarIdentifier> makePyramid(const IdentifyOptions& o) {
  return std::make_unique<PyramidIdentifier>(o);
}
}  // namespace identify_detail

}  // namespace st

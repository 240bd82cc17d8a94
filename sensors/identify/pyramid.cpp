// Mortari's Pyramid (seed 002 ref. [18], seed 004 sec. 5.5.4): a triangle of observed stars
// is matched through three k-vector lookups, then confirmed by a fourth star whose three
// angles to the triangle must match too; confirmed pyramids are verified, those confirmed by
// the most 4th stars first (below).
#include <algorithm>
#include <array>

#include "sensors/identify/algorithms.hpp"
#include "sensors/identify/search_context.hpp"

namespace st {
namespace {

// Pyramids verified per observed triangle when several 4th stars can confirm it, most
// confirmed first. A triangle with a false star (a lamp, a hot-pixel cluster) matches
// hundreds to thousands of catalog triangles under a FOV search's wide gates, and chance
// confirmations by one or two 4th stars are common among them: verified in the order found,
// they used up the whole budget of 300 before any true pyramid (measured: a frame with two
// false stars among the brightest three, no hypothesis matching more than 8 stars). A real
// triangle is confirmed by every real 4th star in view.
constexpr int kMaxPerTriangle = 20;
// Confirmations that get a pyramid verified at once (a clean frame's first triangle is then
// solved after three 4th stars, not all of them); chance ones rarely reach three.
constexpr int kSureConfirmations = 3;

class PyramidIdentifier final : public StarIdentifier {
 public:
  explicit PyramidIdentifier(const IdentifyOptions& o) : StarIdentifier(o) {}
  std::string name() const override { return "pyramid"; }

 private:
  /// Confirmations of one catalog triangle by distinct 4th stars r (the first one's d kept).
  struct Confirmed {
    int count = 0, r = -1;
    uint32_t d = 0;
  };

  void doIdentify(SearchContext& ctx) const override {
    std::vector<std::array<uint32_t, 3>> tris;
    std::vector<Confirmed> confirmed;
    std::vector<StarMatch> seeds(4);
    auto tryPyramid = [&](int i, int j, int k, int r, const std::array<uint32_t, 3>& t,
                          uint32_t d) {
      const int oi[4] = {i, j, k, r};
      const uint32_t si[4] = {t[0], t[1], t[2], d};
      for (int q = 0; q < 4; ++q) {
        seeds[q].obs_index = oi[q];
        seeds[q].star_index = si[q];
      }
      return ctx.tryHypothesis(seeds) || ctx.done();
    };
    // With one possible 4th star every confirmed pyramid is verified as it comes. With more,
    // each catalog triangle counts the 4th stars that confirm it; one reaching
    // kSureConfirmations is verified at once, the others most confirmed first after all 4th
    // stars were tried; kMaxPerTriangle verifications at most per triangle.
    const bool vote = ctx.n > 4;
    std::vector<std::size_t> ranked;
    identify_detail::forEachTriangle(ctx.n, [&](int i, int j, int k) {
      if (ctx.done()) return true;
      tris.clear();
      identify_detail::forEachCatalogTriangle(ctx, i, j, k,
                                              [&](uint32_t a, uint32_t b, uint32_t c) {
                                                tris.push_back({a, b, c});
                                                return false;  // all of them
                                              });
      if (tris.empty()) return false;
      confirmed.assign(tris.size(), Confirmed{});
      int tried = 0;
      // Confirm with a 4th star r: a catalog star d at the right angles from a, b and c.
      // Only the triangles' first stars are looked up: their partners alone are listed.
      StarCounter& firsts = ctx.counter(0);
      firsts.clear();
      for (const auto& t : tris) firsts.add(t[0]);
      const auto isFirst = [&](uint32_t a) { return firsts.get(a) > 0; };
      PartnerLists& lir = ctx.lists(1);
      for (int r = 0; r < ctx.n; ++r) {
        if (r == i || r == j || r == k) continue;
        lir.build(ctx.slice(i, r), isFirst);
        for (std::size_t ti = 0; ti < tris.size(); ++ti) {
          const auto& t = tris[ti];
          bool stop = false, seen = false;
          lir.forEach(t[0], [&](uint32_t d) {
            if (stop || seen || d == t[1] || d == t[2] || !ctx.angleMatches(j, r, t[1], d) ||
                !ctx.angleMatches(k, r, t[2], d))
              return;
            if (!vote) {
              stop = tryPyramid(i, j, k, r, t, d);
              return;
            }
            seen = true;  // one confirmation per 4th star
            Confirmed& c = confirmed[ti];
            if (c.count++ == 0) c.r = r, c.d = d;
            if (c.count == kSureConfirmations && tried < kMaxPerTriangle) {
              ++tried;
              stop = tryPyramid(i, j, k, c.r, t, c.d);
            }
          });
          if (stop) return true;
        }
      }
      if (!vote) return false;
      // Most confirmed first: a real triangle's pyramid is confirmed by every real 4th star.
      ranked.clear();
      for (std::size_t ti = 0; ti < tris.size(); ++ti)  // (those verified already left out)
        if (confirmed[ti].count > 0 && confirmed[ti].count < kSureConfirmations)
          ranked.push_back(ti);
      const std::size_t top =
          std::min<std::size_t>(ranked.size(), static_cast<std::size_t>(kMaxPerTriangle - tried));
      std::partial_sort(ranked.begin(), ranked.begin() + static_cast<std::ptrdiff_t>(top),
                        ranked.end(), [&](std::size_t a, std::size_t b) {
                          return confirmed[a].count > confirmed[b].count ||
                                 (confirmed[a].count == confirmed[b].count && a < b);
                        });
      for (std::size_t q = 0; q < top; ++q) {
        const Confirmed& c = confirmed[ranked[q]];
        if (tryPyramid(i, j, k, c.r, tris[ranked[q]], c.d)) return true;
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

// Shows that an identification algorithm compiled into an executable is one file and ONE
// registration line: "triangle_in_test" (plain k-vector triangles, the Pyramid without its
// 4th-star confirmation: every handed triangle is a hypothesis for the shared verification)
// is registered below, and the family's shared suite (Registry/EveryAlgorithm.* in
// test_identify_statistical.cpp) runs on it without being edited.
#include <vector>

#include "common/family_registry.hpp"
#include "sensors/identify/algorithms.hpp"
#include "sensors/identify/search_context.hpp"

namespace st {
namespace {

class TriangleInTest final : public StarIdentifier {
 public:
  explicit TriangleInTest(const IdentifyOptions& o) : StarIdentifier(o) {}
  std::string name() const override { return "triangle_in_test"; }

 private:
  int minStars() const override { return 3; }
  void doIdentify(SearchContext& ctx) const override {
    std::vector<StarMatch> seeds(3);
    identify_detail::forEachTriangle(ctx.n, [&](int i, int j, int k) {
      if (ctx.done()) return true;
      const PairSlice sij = ctx.slice(i, j);
      ctx.addAttitudes(2.0 * sij.size());
      PartnerLists& lik = ctx.lists(0);
      lik.build(ctx.slice(i, k));
      bool stop = false;
      for (const StarPair* p = sij.begin; p != sij.end && !stop; ++p)
        for (int o = 0; o < 2 && !stop; ++o) {
          const uint32_t a = o ? p->b : p->a, b = o ? p->a : p->b;
          lik.forEach(a, [&](uint32_t c) {
            if (stop || c == b || !ctx.angleMatches(j, k, b, c) ||
                !ctx.sameHandedness(i, j, k, a, b, c))
              return;
            seeds[0] = {static_cast<uint32_t>(i), a};
            seeds[1] = {static_cast<uint32_t>(j), b};
            seeds[2] = {static_cast<uint32_t>(k), c};
            stop = ctx.tryHypothesis(seeds) || ctx.done();
          });
        }
      return stop;
    });
  }
};

std::unique_ptr<StarIdentifier> makeTriangleInTest(const IdentifyOptions& o) {
  return std::make_unique<TriangleInTest>(o);
}

}  // namespace
}  // namespace st

ST_REGISTER_FAMILY_MEMBER(st::StarIdentifier, "triangle_in_test",
                          "k-vector triangles without confirmation, registered by a test",
                          &st::makeTriangleInTest);

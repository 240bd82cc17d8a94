// Shows that an identification algorithm compiled into an executable is one file and ONE
// registration line: "triangle_in_test" (plain k-vector triangles, the Pyramid without its
// 4th-star confirmation: every handed triangle is a hypothesis for the shared verification)
// is registered below, and the family's shared suite (Registry/EveryAlgorithm.* in
// test_identify_statistical.cpp) runs on it without being edited.
#include <vector>

#include "common/family_registry.hpp"
#include "sensors/identify/algorithms.hpp"

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
      return identify_detail::forEachCatalogTriangle(
          ctx, i, j, k, [&](uint32_t a, uint32_t b, uint32_t c) {
            seeds[0] = {static_cast<uint32_t>(i), a};
            seeds[1] = {static_cast<uint32_t>(j), b};
            seeds[2] = {static_cast<uint32_t>(k), c};
            return ctx.tryHypothesis(seeds) || ctx.done();
          });
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

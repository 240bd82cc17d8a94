// Planar and spherical triangle matching (seed 001 sec. II.B/C): an observed triangle is
// characterised by its area and polar moment. Catalog triangles are reached through the
// k-vector (two sides, i-j and i-k, share a vertex); the third side is NOT tested: the
// area and polar moment decide, with tolerances propagated from the side tolerances
// (first-order, by finite differences). Mirror images are rejected by handedness.
#include <array>
#include <cmath>

#include "sensors/identify/algorithms.hpp"
#include "sensors/identify/search_context.hpp"
#include "sensors/identify/triangle_features.hpp"

namespace st {
namespace {

class TriangleIdentifier final : public StarIdentifier {
 public:
  TriangleIdentifier(const IdentifyOptions& o, bool spherical)
      : StarIdentifier(o), spherical_(spherical) {}
  std::string name() const override { return spherical_ ? "spherical" : "planar"; }

 private:
  int minStars() const override { return 3; }

  TriangleFeature feature(const Vec3& a, const Vec3& b, const Vec3& c) const {
    return spherical_ ? sphericalTriangle(a, b, c) : planarTriangle(a, b, c);
  }

  // Tolerance of (area, moment): |dF/dx_v| * tol summed over the three vertices, each vertex
  // moved by its tolerance along both tangent directions.
  std::array<double, 2> tolerance(const SearchContext& ctx, int i, int j, int k) const {
    const int idx[3] = {i, j, k};
    const TriangleFeature f0 = feature(ctx.v(i), ctx.v(j), ctx.v(k));
    double ta = 0, tj = 0;
    for (int v = 0; v < 3; ++v) {
      const Vec3& x = ctx.v(idx[v]);
      const Vec3 e1 = x.unitOrthogonal(), e2 = x.cross(e1);
      const double step = ctx.opt.pair_sigma * ctx.obs[idx[v]].sigma +
                          ctx.opt.scale_tolerance * std::acos(std::min(1.0, x.z()));
      for (const Vec3& e : {e1, e2}) {
        Vec3 p[3] = {ctx.v(i), ctx.v(j), ctx.v(k)};
        p[v] = (x + step * e).normalized();
        const TriangleFeature f = feature(p[0], p[1], p[2]);
        ta += std::abs(f.area - f0.area);
        tj += std::abs(f.polar_moment - f0.polar_moment);
      }
    }
    return {ta, tj};
  }

  void doIdentify(SearchContext& ctx) const override {
    std::vector<StarMatch> seeds(3);
    identify_detail::forEachTriangle(ctx.n, [&](int i, int j, int k) {
      if (ctx.done()) return true;
      const TriangleFeature fo = feature(ctx.v(i), ctx.v(j), ctx.v(k));
      const auto tol = tolerance(ctx, i, j, k);
      const PairSlice sij = ctx.slice(i, j);
      ctx.addAttitudes(2.0 * sij.size());
      PartnerLists& lik = ctx.lists(0);
      lik.build(ctx.slice(i, k));
      for (const StarPair* p = sij.begin; p != sij.end; ++p)
        for (int o = 0; o < 2; ++o) {
          const uint32_t a = o ? p->b : p->a, b = o ? p->a : p->b;
          bool stop = false;
          lik.forEach(a, [&](uint32_t c) {
            if (stop || c == b || !ctx.sameHandedness(i, j, k, a, b, c)) return;
            const TriangleFeature fc = feature(ctx.u(a), ctx.u(b), ctx.u(c));
            if (std::abs(fc.area - fo.area) > tol[0] ||
                std::abs(fc.polar_moment - fo.polar_moment) > tol[1])
              return;
            seeds[0] = {static_cast<uint32_t>(i), a, 0, 0, 0};
            seeds[1] = {static_cast<uint32_t>(j), b, 0, 0, 0};
            seeds[2] = {static_cast<uint32_t>(k), c, 0, 0, 0};
            stop = ctx.tryHypothesis(seeds) || ctx.done();
          });
          if (stop) return true;
        }
      return false;
    });
  }

  bool spherical_;
};

}  // namespace

// The factory the registry table (registry.cpp) names.
namespace identify_detail {
std::unique_ptr<StarIdentifier> makePlanarTriangle(const IdentifyOptions& o) {
  return std::make_unique<TriangleIdentifier>(o, false);
}
std::unique_ptr<StarIdentifier> makeSphericalTriangle(
    const IdentifyOptions& o) {
  return std::make_unique<TriangleIdentifier>(o, true);
}
}  // namespace identify_detail

}  // namespace st

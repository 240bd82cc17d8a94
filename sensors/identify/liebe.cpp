// Liebe's triangular feature (seed 003, "The Triangular Feature", Fig. 6): a star is
// characterised by the angular distance to its first and second neighbour and the angle
// between them at the star. The database side is built from the star database's neighbour
// table (seed 002 Table I); to survive a missing neighbour or a neighbour swap inside the
// tolerance (seed 003 Fig. 13, Table 2 error situations) every pair among the first four
// catalog neighbours is registered, and every pair among the first three observed
// neighbours is queried. Instead of quantised classes (seed 003 "Inclusion of
// Position-Uncertainty") the features are sorted by the first distance and searched with
// tolerances from the centroid sigmas. Stars whose neighbour is farther than the image rim
// are skipped (seed 003 "Initial Estimate").
#include <algorithm>
#include <cmath>

#include "common/attitude.hpp"
#include "sensors/identify/algorithms.hpp"
#include "sensors/identify/search_context.hpp"

namespace st {
namespace {

struct Feature {
  float d1, d2, phi;  // [rad]
  uint32_t s, p, q;   // star, its nearer and its farther neighbour of the pair
};

// Angle at s between the great circles towards p and q.
double vertexAngle(const Vec3& s, const Vec3& p, const Vec3& q) {
  const Vec3 tp = p - s.dot(p) * s, tq = q - s.dot(q) * s;
  return angleBetween(tp, tq);
}

constexpr int kCatalogNeighbours = 4;
constexpr int kObservedNeighbours = 3;

class LiebeIdentifier final : public StarIdentifier {
 public:
  explicit LiebeIdentifier(const IdentifyOptions& o) : StarIdentifier(o) {}
  std::string name() const override { return "liebe"; }

 private:
  int minStars() const override { return 3; }

  void buildIndex(const StarDatabase& db) const {
    if (cached_db_ == &db && cached_n_ == db.stars().size()) return;
    index_.clear();
    const auto& stars = db.stars();
    for (uint32_t s = 0; s < stars.size(); ++s) {
      const uint32_t* nb = db.neighboursBegin(s);
      const int count = std::min<int>(kCatalogNeighbours, db.neighboursEnd(s) - nb);
      for (int a = 0; a < count; ++a)
        for (int b = a + 1; b < count; ++b) {
          const Vec3 &us = stars[s].u_i, &up = stars[nb[a]].u_i, &uq = stars[nb[b]].u_i;
          index_.push_back({float(angleBetween(us, up)), float(angleBetween(us, uq)),
                            float(vertexAngle(us, up, uq)), s, nb[a], nb[b]});
        }
    }
    std::sort(index_.begin(), index_.end(),
              [](const Feature& x, const Feature& y) { return x.d1 < y.d1; });
    cached_db_ = &db;
    cached_n_ = stars.size();
  }

  void doIdentify(SearchContext& ctx) const override {
    buildIndex(ctx.db);
    const int n_all = static_cast<int>(ctx.obs.size());
    const double k = ctx.opt.pair_sigma, scale = ctx.opt.scale_tolerance;
    std::vector<std::pair<double, int>> nbrs;
    std::vector<StarMatch> seeds(3);
    for (int i = 0; i < ctx.n && !ctx.done(); ++i) {
      const StarObservation& oi = ctx.obs[i];
      nbrs.clear();
      for (int j = 0; j < n_all; ++j)
        if (j != i) nbrs.push_back({angleBetween(oi.v_cam, ctx.obs[j].v_cam), j});
      const int m = std::min<int>(kObservedNeighbours, nbrs.size());
      std::partial_sort(nbrs.begin(), nbrs.begin() + m, nbrs.end());
      const double rim_px = std::min({oi.px.x() + 0.5, oi.px.y() + 0.5,
                                      ctx.camera.width() - 0.5 - oi.px.x(),
                                      ctx.camera.height() - 0.5 - oi.px.y()});
      const double rim = rim_px * ctx.camera.pixelScale();
      for (int a = 0; a < m; ++a)
        for (int b = a + 1; b < m; ++b) {
          const auto [d1, p] = nbrs[a];
          const auto [d2, q] = nbrs[b];
          if (d2 > rim) continue;  // the true 2nd neighbour might be outside the image
          const double sp = ctx.obs[p].sigma, sq = ctx.obs[q].sigma, si = oi.sigma;
          const double t1 = k * std::hypot(si, sp) + scale * d1;
          const double t2 = k * std::hypot(si, sq) + scale * d2;
          const double tphi = k * (std::hypot(sp, si) / d1 + std::hypot(sq, si) / d2);
          const double phi = vertexAngle(oi.v_cam, ctx.obs[p].v_cam, ctx.obs[q].v_cam);
          auto lo = std::lower_bound(index_.begin(), index_.end(), float(d1 - t1),
                                     [](const Feature& f, float v) { return f.d1 < v; });
          auto hi = std::upper_bound(lo, index_.end(), float(d1 + t1),
                                     [](float v, const Feature& f) { return v < f.d1; });
          ctx.addAttitudes(static_cast<double>(hi - lo));
          ctx.addCandidates(hi - lo);
          for (auto f = lo; f != hi; ++f) {
            if (std::abs(f->d2 - d2) > t2 || std::abs(f->phi - phi) > tphi) continue;
            const double so = oi.v_cam.dot(ctx.obs[p].v_cam.cross(ctx.obs[q].v_cam));
            const double sc = ctx.u(f->s).dot(ctx.u(f->p).cross(ctx.u(f->q)));
            if ((so > 0) != (sc > 0)) continue;
            seeds[0] = {static_cast<uint32_t>(i), f->s, 0, 0, 0};
            seeds[1] = {static_cast<uint32_t>(p), f->p, 0, 0, 0};
            seeds[2] = {static_cast<uint32_t>(q), f->q, 0, 0, 0};
            if (ctx.tryHypothesis(seeds) || ctx.done()) return;
          }
        }
    }
  }

  mutable const StarDatabase* cached_db_ = nullptr;
  mutable std::size_t cached_n_ = 0;
  mutable std::vector<Feature> index_;
};

}  // namespace

// The factory the registry table (registry.cpp) names.
namespace identify_detail {
std::unique_ptr<StarIdentifier> makeLiebe(const IdentifyOptions& o) {
  return std::make_unique<LiebeIdentifier>(o);
}
}  // namespace identify_detail

}  // namespace st

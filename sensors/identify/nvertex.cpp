// n-vertex match for n = 3, 4, 5 (seed 004 sec. 5.5.4, eq. 6.7; "three versions ... one each
// for values of n equal to 3, 4, and 5"): the n(n-1)/2 baselines of n observed stars are
// looked up at once. A candidate for the first star A must appear in the slices of all of
// its baselines AB, AC, ... (the S-matrix "self-consistency", Table 5.4's row test); every
// other baseline must then hold between the assigned candidates. Every consistent n-vertex
// assignment is verified.
#include <array>
#include <string>

#include "common/check.hpp"
#include "sensors/identify/algorithms.hpp"
#include "sensors/identify/search_context.hpp"

namespace st {
namespace {

constexpr int kMaxVertices = 5;

class NVertexIdentifier final : public StarIdentifier {
 public:
  NVertexIdentifier(const IdentifyOptions& o, int n) : StarIdentifier(o), n_(n) {
    ST_ASSERT(n >= 3 && n <= kMaxVertices);
  }
  std::string name() const override { return n_ == 4 ? "nvertex" : "nvertex" + std::to_string(n_); }
  int minStars() const override { return n_; }

 private:
  using Ids = std::array<int, kMaxVertices>;
  using Stars = std::array<uint32_t, kMaxVertices>;

  /// Assigns vertex k (>= 2) among the partners of A in baseline A-k, then the next ones.
  /// Returns true when the search must stop (solved or out of budget).
  bool assign(SearchContext& ctx, const Ids& o, Stars& s, int k,
              std::vector<StarMatch>& seeds) const {
    if (k >= n_ || k >= kMaxVertices) {  // (the second bound for the compiler's sake)
      for (int q = 0; q < n_ && q < kMaxVertices; ++q) seeds[q] = {static_cast<uint32_t>(o[q]), s[q], 0, 0, 0};
      return ctx.tryHypothesis(seeds) || ctx.done();
    }
    bool stop = false;
    ctx.lists(k - 2).forEach(s[0], [&](uint32_t c) {
      if (stop) return;
      for (int j = 1; j < k; ++j) {
        if (c == s[j]) return;
        // Eq. 6.7: every baseline between assigned vertices must hold, not only A's.
        if (!ctx.angleMatches(o[j], o[k], s[j], c)) return;
      }
      if (k == 2 && !ctx.sameHandedness(o[0], o[1], o[2], s[0], s[1], c)) return;
      s[k] = c;
      stop = assign(ctx, o, s, k + 1, seeds);
    });
    return stop;
  }

  bool tryPolygon(SearchContext& ctx, const Ids& o, std::vector<StarMatch>& seeds) const {
    const PairSlice s01 = ctx.slice(o[0], o[1]);
    ctx.addAttitudes(2.0 * s01.size());
    for (int k = 2; k < n_ && k < kMaxVertices; ++k) ctx.lists(k - 2).build(ctx.slice(o[0], o[k]));
    Stars s{};
    for (const StarPair* p = s01.begin; p != s01.end; ++p)
      for (int w = 0; w < 2; ++w) {
        s[0] = w ? p->b : p->a;
        s[1] = w ? p->a : p->b;
        bool in_every_column = true;  // A must be in columns AB, AC, ... of S
        for (int k = 2; k < n_ && k < kMaxVertices; ++k) in_every_column = in_every_column && ctx.lists(k - 2).has(s[0]);
        if (!in_every_column) continue;
        if (assign(ctx, o, s, 2, seeds)) return true;
      }
    return false;
  }

  /// Spacings d[1..n-1] between the chosen observations, outermost first, then the first
  /// observation: the triangle match's loop (Mortari's pattern), which changes the stars of
  /// consecutive polygons as much as it can.
  bool spacings(SearchContext& ctx, std::array<int, kMaxVertices>& d, int level, int used,
                std::vector<StarMatch>& seeds) const {
    if (level >= n_ || level >= kMaxVertices) {
      for (int i = 0; i + used < ctx.n; ++i) {
        if (ctx.done()) return true;
        Ids o{};
        o[0] = i;
        for (int q = 1; q < n_ && q < kMaxVertices; ++q) o[q] = o[q - 1] + d[q];
        if (tryPolygon(ctx, o, seeds)) return true;
      }
      return false;
    }
    const int left = n_ - 1 - level;  // spacings still to choose after this one
    for (d[level] = 1; used + d[level] + left <= ctx.n - 1; ++d[level])
      if (spacings(ctx, d, level + 1, used + d[level], seeds)) return true;
    return false;
  }

  void doIdentify(SearchContext& ctx) const override {
    std::vector<StarMatch> seeds(n_);
    std::array<int, kMaxVertices> d{};
    spacings(ctx, d, 1, 0, seeds);
  }

  int n_;
};

}  // namespace

// The factories the registry table (registry.cpp) names.
namespace identify_detail {
std::unique_ptr<StarIdentifier> makeNVertex3(const IdentifyOptions& o) {
  return std::make_unique<NVertexIdentifier>(o, 3);
}
std::unique_ptr<StarIdentifier> makeNVertex(const IdentifyOptions& o) {
  return std::make_unique<NVertexIdentifier>(o, 4);
}
std::unique_ptr<StarIdentifier> makeNVertex5(const IdentifyOptions& o) {
  return std::make_unique<NVertexIdentifier>(o, 5);
}
}  // namespace identify_detail

}  // namespace st

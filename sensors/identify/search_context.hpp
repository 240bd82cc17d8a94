/// @file search_context.hpp
/// What an identification algorithm works with during one identify() call: the observations
/// used to form patterns, their inter-star angles and k-vector tolerances, catalog pair
/// lookups, scratch lists, and tryHypothesis() which runs the shared verification.
/// Internal to sensors/identify/ (the algorithms' .cpp files include it).
#pragma once
#include <chrono>
#include <cstdint>
#include <vector>

#include "sensors/identify/identifier.hpp"

namespace st {

/// For one k-vector slice: the partners of each catalog star, without sorting or clearing
/// (epoch stamps), so building costs O(slice) and a lookup O(partners).
class PartnerLists {
 public:
  static constexpr uint32_t kNone = 0xffffffffu;
  void reset(std::size_t n_stars);
  void build(const PairSlice& s);
  /// The partners of the stars `keep(a)` accepts only: a search that looks up few stars
  /// then pays a read per pair instead of a list entry (the entries are the cost).
  template <class Keep>
  void build(const PairSlice& s, Keep&& keep) {
    ++epoch_;
    partner_.clear();
    next_.clear();
    for (const StarPair* p = s.begin; p != s.end; ++p) {
      if (keep(p->a)) push(p->a, p->b);
      if (keep(p->b)) push(p->b, p->a);
    }
  }
  bool has(uint32_t a) const { return stamp_[a] == epoch_; }
  template <class F>
  void forEach(uint32_t a, F&& f) const {
    if (!has(a)) return;
    for (uint32_t e = head_[a]; e != kNone; e = next_[e]) f(partner_[e]);
  }

 private:
  void push(uint32_t a, uint32_t b);
  std::vector<uint32_t> stamp_, head_, next_, partner_;
  uint32_t epoch_ = 0;
};

/// A per-star counter reset in O(1) (epoch stamps).
class StarCounter {
 public:
  void reset(std::size_t n_stars);
  void clear() { ++epoch_; }
  uint32_t get(uint32_t a) const { return stamp_[a] == epoch_ ? count_[a] : 0; }
  uint32_t add(uint32_t a) {
    if (stamp_[a] != epoch_) stamp_[a] = epoch_, count_[a] = 0;
    return ++count_[a];
  }
  /// Tag per star (e.g. the last observation that counted it), valid in this epoch.
  uint32_t tag(uint32_t a) const { return stamp_[a] == epoch_ ? tag_[a] : 0xffffffffu; }
  void setTag(uint32_t a, uint32_t t) {
    if (stamp_[a] != epoch_) stamp_[a] = epoch_, count_[a] = 0;
    tag_[a] = t;
  }

 private:
  std::vector<uint32_t> stamp_, count_, tag_;
  uint32_t epoch_ = 1;
};

class SearchContext {
 public:
  SearchContext(const std::vector<StarObservation>& obs, const StarDatabase& db,
                const CameraModel& camera, const IdentifyOptions& opt, const Verifier& verifier,
                int n_used, std::vector<PartnerLists>& lists, std::vector<StarCounter>& counters);

  const std::vector<StarObservation>& obs;
  const StarDatabase& db;
  const CameraModel& camera;
  const IdentifyOptions& opt;
  const int n;  ///< patterns use observations 0..n-1 (the brightest)

  double theta(int i, int j) const { return theta_[i * n + j]; }
  double tol(int i, int j) const { return tol_[i * n + j]; }
  /// Catalog pairs whose separation is within tol(i,j) of theta(i,j) (k-vector lookup);
  /// counted in candidatesExamined().
  PairSlice slice(int i, int j);
  /// Whether catalog stars a, b are separated like observations i, j.
  bool angleMatches(int i, int j, uint32_t a, uint32_t b) const {
    const double d = db.stars()[a].u_i.dot(db.stars()[b].u_i);
    return d >= cos_lo_[i * n + j] && d <= cos_hi_[i * n + j];
  }
  /// Same handedness of the observed triangle (i, j, k) and the catalog triangle (a, b, c):
  /// rejects mirror images, which have the same side lengths.
  bool sameHandedness(int i, int j, int k, uint32_t a, uint32_t b, uint32_t c) const;
  const Vec3& u(uint32_t star) const { return db.stars()[star].u_i; }
  const Vec3& v(int i) const { return obs[i].v_cam; }

  /// A in the false-match model: candidate attitudes looked at so far.
  void addAttitudes(double a) { attitudes_ += a; }
  double attitudesExamined() const { return attitudes_; }
  void addCandidates(long c) { candidates_ += c; }

  /// Verifies "observation seeds[k].obs_index is catalog star seeds[k].star_index". Returns
  /// true when accepted: the algorithm must then return.
  bool tryHypothesis(const std::vector<StarMatch>& seeds);
  /// True when solved or a budget (verifications, candidates) is used up.
  bool done() const;

  PartnerLists& lists(std::size_t k) { return lists_.at(k); }
  StarCounter& counter(std::size_t k) { return counters_.at(k); }

  // Results read by StarIdentifier::identify.
  bool solved = false;
  bool any_hypothesis = false;
  VerificationResult accepted, best_rejected;
  int hypotheses = 0;
  double verify_seconds = 0;

 private:
  const Verifier& verifier_;
  std::vector<PartnerLists>& lists_;
  std::vector<StarCounter>& counters_;
  std::vector<double> theta_, tol_, cos_lo_, cos_hi_;
  double attitudes_ = 0;
  long candidates_ = 0;
  mutable unsigned done_calls_ = 0;  ///< the deadline's clock is read every 256th done()
};

}  // namespace st

// Teeth for each identifier's own pattern rules (issue 17 item 1), without the shared
// verification's rescue: the verification accepts any pattern that leads to the right stars,
// so "never wrong" says nothing about whether a paper's rule works. Here each identifier
// proposes ONE hypothesis (verification off, max_verifications = 1, no retry) and the test
// reads that hypothesis's seed pairs exactly as the identifier built them: a Wahba solver
// registered by this file records the vector pairs of the first solve of the search, which
// is verifySeeds() solving the seeds (verify.cpp). A seed is right when its observation is
// the catalog star it was paired with (the scene's truth), a hypothesis when all are.
//
// Each rule is a filter on candidates: with the rule, the first candidate the search meets is
// the true pattern; without it, a chance pattern that passes the weaker test comes first.
// Rates are over fixed-seed scenes and were measured with and without each rule
// (scripts/mutants.sh, docs/mutants.md); each bound sits between the two, the measured
// numbers are given at each test.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "common/family_registry.hpp"
#include "sensors/attitude/wahba.hpp"
#include "sensors/identify/identifier.hpp"
#include "tests/identify/scene.hpp"

namespace st {
namespace {

// ---- the seed recorder -------------------------------------------------------------------

struct SeedRecorder {
  bool armed = false;
  std::vector<VectorObservation> first;  ///< pairs of the first solve after arming
};
SeedRecorder& recorder() {
  static SeedRecorder r;
  return r;
}

class SeedRecordingSolver final : public WahbaSolver {
 public:
  std::string name() const override { return "seed_recorder_in_test"; }

 private:
  WahbaSolution doSolve(const std::vector<VectorObservation>& obs) const override {
    SeedRecorder& r = recorder();
    if (r.armed) {
      r.first = obs;
      r.armed = false;
    }
    return quest_->solve(obs);
  }
  std::unique_ptr<WahbaSolver> quest_ = WahbaSolver::create("quest");
};

std::unique_ptr<WahbaSolver> makeSeedRecorder() { return std::make_unique<SeedRecordingSolver>(); }

// ---- one hypothesis per scene -------------------------------------------------------------

IdentifyOptions oneHypothesis(IdentifyOptions o = {}) {
  o.solver = "seed_recorder_in_test";
  o.verify.enabled = false;  // the rescue this file is about
  o.max_verifications = 1;
  o.max_stars_retry = 0;
  return o;
}

struct Hypothesis {
  bool made = false;
  bool right = false;
  bool uses_false_star = false;
  bool first_right = false;       ///< the first seed (voting: the reference star)
  bool first_is_false = false;    ///< the first seed is a false star
  std::size_t seeds = 0;
  std::vector<int> obs;           ///< the seeds' observation indices, in seed order
};

Hypothesis firstHypothesis(const StarIdentifier& id, const test::Scene& sc,
                           const CameraModel& cam) {
  const StarDatabase& db = test::testDatabase();
  const std::vector<StarObservation> obs = toStarObservations(sc.centroids, cam);
  recorder() = SeedRecorder{};
  recorder().armed = true;
  id.identify(obs, db, cam);
  recorder().armed = false;
  Hypothesis h;
  const std::vector<VectorObservation>& seeds = recorder().first;
  if (seeds.empty()) return h;
  h.made = true;
  h.right = true;
  h.seeds = seeds.size();
  for (const VectorObservation& s : seeds) {
    int k = -1;
    for (std::size_t j = 0; j < obs.size() && k < 0; ++j)
      if (obs[j].v_cam == s.b) k = static_cast<int>(j);
    EXPECT_GE(k, 0) << "a seed vector that is no observation";
    h.obs.push_back(k);
    const int truth = k >= 0 ? sc.truth[k] : -1;
    const bool right = truth >= 0 && db.stars()[truth].u_i == s.r;
    if (&s == &seeds.front()) h.first_right = right, h.first_is_false = truth < 0;
    if (truth < 0) h.uses_false_star = true;
    if (!right) h.right = false;
  }
  return h;
}

// Liebe's seeds are (star, nearer neighbour, farther neighbour): whether the farther one is
// farther from the star than the image rim (liebe.cpp, seed 003 "Initial Estimate").
bool beyondRim(const test::Scene& sc, const CameraModel& cam, int star, int farther) {
  const Vec2 p = sc.centroids[star].px;
  const double rim_px = std::min({p.x() + 0.5, p.y() + 0.5, cam.width() - 0.5 - p.x(),
                                  cam.height() - 0.5 - p.y()});
  const Vec3 a = cam.pixelToVector(p), b = cam.pixelToVector(sc.centroids[farther].px);
  return std::atan2(a.cross(b).norm(), a.dot(b)) > rim_px * cam.pixelScale();
}

struct Rate {
  int scenes = 0, made = 0, right = 0, false_star = 0;
  int rim_feature = 0;  ///< Liebe: hypotheses whose feature reaches beyond the image rim
  int first_right = 0, first_false = 0;  ///< the first seed right / a false star
};

/// `scenes` fixed-seed scenes; `edit` may change each scene (e.g. put a spike first) and
/// returns false to draw another scene instead.
template <class Edit>
Rate firstHypothesisRate(const std::string& algorithm, const IdentifyOptions& opt,
                         const test::SceneParams& sp, int scenes, uint64_t seed, Edit edit,
                         double hfov_deg = 15.0) {
  std::string err;
  auto id = StarIdentifier::create(algorithm, oneHypothesis(opt), &err);
  EXPECT_TRUE(id) << err;
  if (!id) return {};
  const CameraModel cam = test::testCamera(hfov_deg);
  std::mt19937_64 rng(seed);
  Rate r;
  for (int k = 0; k < scenes;) {
    test::Scene sc = test::makeScene(rng, test::testDatabase(), cam, sp, test::randomAttitude(rng));
    if (!edit(sc, rng, cam)) continue;
    ++k;
    const Hypothesis h = firstHypothesis(*id, sc, cam);
    ++r.scenes;
    r.rim_feature += algorithm == "liebe" && h.made && beyondRim(sc, cam, h.obs[0], h.obs[2]);
    r.made += h.made;
    r.right += h.right;
    r.false_star += h.uses_false_star;
    r.first_right += h.first_right;
    r.first_false += h.first_is_false;
  }
  std::printf("%-10s first hypotheses: %d scenes, %d made, %d right, %d with a false star; "
              "first seed right %d, a false star %d; %d Liebe features beyond the rim\n",
              algorithm.c_str(), r.scenes, r.made, r.right, r.false_star, r.first_right,
              r.first_false, r.rim_feature);
  return r;
}

Rate firstHypothesisRate(const std::string& algorithm, const IdentifyOptions& opt,
                         const test::SceneParams& sp, int scenes, uint64_t seed) {
  return firstHypothesisRate(algorithm, opt, sp, scenes, seed,
                             [](test::Scene&, std::mt19937_64&, const CameraModel&) { return true; });
}

test::SceneParams clean() {
  test::SceneParams sp;
  sp.false_min = sp.false_max = 0;
  sp.drop_fraction = 0;
  return sp;
}

// The recorder sees exactly the seeds: a hand-made hypothesis is read back pair for pair.
TEST(IdentifyRules, TheRecorderReadsTheSeedsOfTheFirstHypothesis) {
  const CameraModel cam = test::testCamera();
  std::mt19937_64 rng(5);
  const test::Scene sc =
      test::makeScene(rng, test::testDatabase(), cam, clean(), test::randomAttitude(rng));
  auto id = StarIdentifier::create("pyramid", oneHypothesis());
  ASSERT_TRUE(id);
  const Hypothesis h = firstHypothesis(*id, sc, cam);
  EXPECT_TRUE(h.made);
  EXPECT_EQ(h.seeds, 4u);  // Pyramid: a triangle and its confirming 4th star
  EXPECT_TRUE(h.right);
}

}  // namespace
}  // namespace st

ST_REGISTER_FAMILY_MEMBER(st::WahbaSolver, "seed_recorder_in_test",
                          "QUEST that records the seed pairs it is given (identify rule tests)",
                          &st::makeSeedRecorder);

namespace st {
namespace {

// ---- the rules ---------------------------------------------------------------------------

// Pyramid (seed 002 ref. [18]): a triangle is a hypothesis only when a 4th star has the
// right angles to all three of its stars. 0.5 px noise (wider slices, more chance partners):
// measured 197 of 200 right; with only the 4th star's angle to the first star, 59.
TEST(IdentifyRules, PyramidFourthStarConfirmsTheTriangle) {
  test::SceneParams sp = clean();
  sp.noise_px = 0.5;
  const Rate r = firstHypothesisRate("pyramid", {}, sp, 200, 101);
  EXPECT_GE(r.right, 190);
}

// Seed 001: planar and spherical triangles are matched by area and polar moment; the k-vector
// gives only two sides (i-j, i-k), so without the comparison any catalog star at the i-k
// angle from a completes the triangle.
// Measured on these 400 scenes: 366 (planar) and 375 (spherical) right with both, 330-348
// with one alone (docs/mutants.md); on 100 scenes 2 with neither. The bound sits between.
TEST(IdentifyRules, PlanarAreaAndPolarMomentPickTheTriangle) {
  const Rate r = firstHypothesisRate("planar", {}, clean(), 400, 102);
  EXPECT_GE(r.right, 355);
}
TEST(IdentifyRules, SphericalAreaAndPolarMomentPickTheTriangle) {
  const Rate r = firstHypothesisRate("spherical", {}, clean(), 400, 103);
  EXPECT_GE(r.right, 355);
}

// Seed 003: a star's feature is the distances to its two neighbours AND the angle between
// them at the star.
TEST(IdentifyRules, LiebeVertexAngleSeparatesFeatures) {
  const Rate r = firstHypothesisRate("liebe", {}, clean(), 100, 104);
  EXPECT_GE(r.right, 90);
}

// Seed 003 "Initial Estimate": a star whose 2nd neighbour lies farther than the image rim
// may have its true neighbour outside the image: that feature is not looked up. Scenes where
// the brightest star (the first one queried) is such a star and one of its two nearest
// catalog stars is indeed outside the image. No hypothesis may come from such a feature.
// Without the rule 80 of these 100 first hypotheses come from such a feature. (Measured: the
// rule does not make the first hypothesis more often right, 100/94/72 right with it vs
// 99/94/84 without at 0.1/0.3/0.5 px noise: the catalog side registers every pair among four
// neighbours, so a missing neighbour is already survived (seed 003 Fig. 13).)
TEST(IdentifyRules, LiebeSkipsStarsWhoseNeighbourMayLieBeyondTheRim) {
  auto nearRim = [](test::Scene& sc, std::mt19937_64&, const CameraModel& cam) {
    const Vec2 p = sc.centroids.front().px;
    const double rim = std::min({p.x() + 0.5, p.y() + 0.5, cam.width() - 0.5 - p.x(),
                                 cam.height() - 0.5 - p.y()});
    std::vector<double> d;
    for (std::size_t k = 1; k < sc.centroids.size(); ++k)
      d.push_back((sc.centroids[k].px - p).norm());
    if (d.size() < 3) return false;
    std::sort(d.begin(), d.end());
    if (!(d[1] > rim)) return false;  // its 2nd observed neighbour is farther than the rim
    // ... and one of its two nearest catalog stars is outside the image (so the observed
    // neighbours are not its true ones).
    const StarDatabase& db = test::testDatabase();
    const uint32_t s = static_cast<uint32_t>(sc.truth.front());
    const uint32_t* nb = db.neighboursBegin(s);
    for (int k = 0; k < 2 && nb + k < db.neighboursEnd(s); ++k)
      if (std::find(sc.truth.begin(), sc.truth.end(), static_cast<int>(nb[k])) == sc.truth.end())
        return true;
    return false;
  };
  const Rate r = firstHypothesisRate("liebe", {}, clean(), 100, 105, nearRim);
  EXPECT_EQ(r.rim_feature, 0);
  EXPECT_GE(r.right, 95);
}

// Seed 004 eq. 6.7: all six baselines of the four stars must hold. 0.5 px noise: measured
// 199 of 200 right. (Baseline CD alone matters little: without it 194; the other five
// nearly fix the quad.)
TEST(IdentifyRules, NVertexChecksEveryBaseline) {
  test::SceneParams sp = clean();
  sp.noise_px = 0.5;
  const Rate r = firstHypothesisRate("nvertex", {}, sp, 200, 106);
  EXPECT_GE(r.right, 190);
}

// The same rule for n = 3 (baseline BC between the candidates of B and C) and n = 5 (the six
// baselines among B..E), the other two versions of seed 004 sec. 5.5.4. 200 scenes each;
// measured with the check / without it (scripts/mutants.sh nvertex-baselines):
//   nvertex3 at 0.1 px: 190 / 2 right (at 0.5 px only 23 with it: three baselines of a V <= 6
//   catalog are not unique at that noise, which is why the seed's n goes up to 5);
//   nvertex5 at 0.5 px: 199 / 0 right.
TEST(IdentifyRules, NVertexThreeAndFiveCheckEveryBaseline) {
  test::SceneParams sp = clean();
  sp.noise_px = 0.1;
  const Rate r3 = firstHypothesisRate("nvertex3", {}, sp, 200, 106);
  EXPECT_EQ(r3.made, 200);
  EXPECT_GE(r3.right, 175);  // binomial(200, 0.95): 5 sigma below the measured 190
  sp.noise_px = 0.5;
  const Rate r5 = firstHypothesisRate("nvertex5", {}, sp, 200, 106);
  EXPECT_EQ(r5.made, 200);
  EXPECT_GE(r5.right, 190);
}

// Seed 000 "Reference-star": a spike (a false star) as the reference must not vote. Its
// slices (pairs at its angles to the others) share no catalog star but by chance, so a star
// reaches the count the spike bound asks for, f1 >= (n-1) - n_smax with n_smax = n/4 (and
// n_x <= n_smax empty slices), only by chance, and then the next reference is taken. The
// spike is put first (brightest), where the search starts; the reference is the first seed.
// In this catalog (V <= 6, +-30" slices of 50-575 pairs: a catalog star lies in a slice by
// chance with p ~ 0.1) 8 of 11 slices happen by chance: measured 7 spike references in
// these 100 scenes (each with 12 stars used; the verification rejects them). Without the
// bound almost every first hypothesis has the spike as reference (docs/mutants.md).
TEST(IdentifyRules, VotingSpikeReferenceRarelyVotes) {
  auto spikeFirst = [](test::Scene& sc, std::mt19937_64& rng, const CameraModel& cam) {
    std::uniform_real_distribution<double> u01;
    Centroid c;
    c.px = Vec2(20 + u01(rng) * (cam.width() - 40), 20 + u01(rng) * (cam.height() - 40));
    c.cov_px = sc.centroids.front().cov_px;
    c.flux = 2 * sc.centroids.front().flux;
    sc.centroids.insert(sc.centroids.begin(), c);
    sc.truth.insert(sc.truth.begin(), -1);
    return true;
  };
  const Rate r = firstHypothesisRate("voting", {}, clean(), 100, 107, spikeFirst);
  EXPECT_LE(r.first_false, 20);  // measured 7; a binomial(100, 0.07) exceeds 20 with P ~ 1e-4
  EXPECT_GE(r.first_right, 80);  // measured 93
}

// Seed 000 eq. 15: companion k is named only when the reference's star appears exactly once
// in the k-th slice.
TEST(IdentifyRules, VotingNamesOnlyUnambiguousCompanions) {
  const Rate r = firstHypothesisRate("voting", {}, clean(), 100, 108);
  EXPECT_GE(r.right, 95);
}

}  // namespace
}  // namespace st

namespace st {
namespace {

// Found by this audit, not in the list: the handedness rule. A mirror image of a
// pattern has the same sides, areas and polar moments; only the sign of the triple product
// tells them apart (SearchContext::sameHandedness for pyramid, planar, spherical and nvertex;
// Liebe's own test of the feature's orientation). On a mirrored sky (the image flipped left
// to right) the pattern stage must not pair the observations with the stars they mirror.
// (Voting uses pairs only, which a mirror keeps; its hypotheses fail in the attitude fit.)
TEST(IdentifyRules, MirroredSkyIsNotMatchedByItsMirrorImage) {
  auto mirror = [](test::Scene& sc, std::mt19937_64&, const CameraModel& cam) {
    for (Centroid& c : sc.centroids) c.px.x() = cam.width() - 1.0 - c.px.x();
    return true;
  };
  for (const std::string algorithm : {"pyramid", "planar", "nvertex", "liebe"}) {
    SCOPED_TRACE(algorithm);
    const Rate r = firstHypothesisRate(algorithm, {}, clean(), 50, 109, mirror);
    // "right" here: every seed paired with the star it mirrors. Measured 1 of 50 (pyramid),
    // 0 for the others: a nearly collinear triangle is its own mirror image within the noise.
    EXPECT_LE(r.right, 2);
  }
}

}  // namespace
}  // namespace st

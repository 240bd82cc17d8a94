#include "navigation/truth_scoring.hpp"

#include "sensors/mrpt/rawlog_contract.hpp"

namespace st {

namespace {

/// Two true stars closer than this make one image peak (two Gaussian PSFs of sigma s merge
/// below ~2 s); the database merges such doubles under the brighter member's id, so naming
/// either member of the pair is right. 2 PSF sigma of the simulated scenes (their sensors'
/// psf_sigma_px is 1.0). The truth does not carry the PSF, and the detector's guess (1.2 px)
/// would score more leniently.
constexpr double kUnresolvedSeparationPx = 2.0;

struct IdentityScore {
  int misidentified = 0, blend_claims = 0;
};

/// The matched stars of head `head` against that head's true stars.
IdentityScore scoreIdentities(const CObservationStarTracker& st, const FrameTruth& truth, int head) {
  IdentityScore score;
  for (const MatchedStar& m : st.stars) {
    const TruthStar* nearest = nullptr;
    const TruthStar* claimed = nullptr;
    for (const TruthStar& t : truth.stars) {
      if (t.head != head) continue;
      if (!nearest || (t.px - m.px).squaredNorm() < (nearest->px - m.px).squaredNorm())
        nearest = &t;
      if (t.id == m.catalog_id) claimed = &t;
    }
    if (claimed == nearest) continue;
    if (claimed && (claimed->px - nearest->px).norm() < kUnresolvedSeparationPx) {
      ++score.blend_claims;
    } else {
      ++score.misidentified;
    }
  }
  return score;
}

}  // namespace

void scoreTruth(NavStep& s, const mrpt::obs::CObservation6DFeatures& obs,
                const std::vector<CObservationStarTracker::Ptr>& fixes) {
  const FrameTruth truth = truthFromObservation(obs);
  s.has_truth = true;
  s.q_true = truth.q_ib;
  if (s.initialized) {
    s.error = attitudeError(s.q_ib, s.q_true);
    s.nees = attitudeNees(s.q_ib, s.P_att, s.q_true);
  }
  if (s.fix) {
    s.fix_error = attitudeError(s.q_fix, s.q_true);
    s.fix_nees = attitudeNees(s.q_fix, s.cov_fix, s.q_true);
  }
  for (std::size_t h = 0; h < s.heads.size(); ++h) {
    NavHead& head = s.heads[h];
    if (!head.fix) continue;
    // In the head's own frame: its roll is about its own boresight.
    const Quat q_bc(head.R_body_cam);
    head.fix_error = attitudeError(canonical(head.q_fix * q_bc), canonical(s.q_true * q_bc));
  }
  if (truth.stars.empty()) return;
  for (std::size_t h = 0; h < fixes.size(); ++h) {
    if (!fixes[h]) continue;
    const IdentityScore score = scoreIdentities(*fixes[h], truth, static_cast<int>(h));
    s.misidentified += score.misidentified;
    s.blend_claims += score.blend_claims;
    if (h < s.heads.size()) s.heads[h].misidentified = score.misidentified;
    s.ids_scored = true;
  }
}

}  // namespace st

/// @file few_stars.hpp
/// Lost-in-space with two or three stars: the magnitude tie-break (seed 000: "the use of the
/// magnitude information could be restricted to the ambiguities only when they actually
/// occur, e.g. when only n = 2 stars are available"). Internal to sensors/identify/; runs
/// from StarIdentifier::identify when IdentifyOptions::magnitude_sigma > 0 and the field has
/// fewer stars than the algorithm and the verification need.
///
/// Every catalog pattern that fits the geometry (a pair in both orders; a triangle with its
/// handedness, algorithms.hpp forEachCatalogTriangle) is enumerated, none skipped, and kept
/// only when
///  1. magnitudes: with m_s = -2.5 log10(brightness_s) and the zero point free (only relative
///     magnitudes can be trusted, seed 000), chi2 = sum_s (V_s - m_s - ZP^)^2 / sigma_m^2 <=
///     the chi-square (n - 1 dof) quantile at 1 - residual_alpha;
///  2. no absent star: no catalog star predicted in the image (away from the observations and
///     the border) is brighter than the faintest matched star by more than the magnitude
///     window w = sigma_m sqrt(2 q) (q the 1-dof quantile): it would have been seen.
/// One survivor is the solution; two or more are refused as ambiguous, never guessed.
///
/// False-match probability of the survivor (H0: the observations are not these catalog
/// stars: a spike, a star missing from the catalog, another part of the sky). The observed
/// pair fits by chance the A candidate attitudes examined (2 x the k-vector slice). Given
/// the pair, a third observation fits a catalog star by chance with p = N_fov a / Omega_fov
/// (N_fov database stars expected in the image of solid angle Omega_fov, a = 4 tol_1 tol_2 /
/// sin(phi) the region where the two side tolerances cross at angle phi), and each star
/// beyond the first passes the magnitude window with q_s = the fraction of database stars
/// whose V lies within +-w of the V it needs (a box around the chi-square ellipse: an upper
/// bound). P_false = min(1, A p^(n - 2) prod q_s); accepted when <= false_match_threshold
/// (verify.hpp). The absent-star test is not counted as evidence (conservative).
#pragma once
#include "sensors/attitude/wahba.hpp"
#include "sensors/identify/search_context.hpp"

namespace st::identify_detail {

struct FewStarOutcome {
  bool solved = false;
  bool any_candidate = false;  ///< some pattern fitted the geometry
  std::string reason;          ///< why not solved
  VerificationResult result;   ///< of the survivor (accepted or not), else empty
  int geometric = 0;           ///< patterns fitting the geometry
  int magnitude_ok = 0;        ///< of those, passing the magnitude test
  int survivors = 0;           ///< of those, without an absent star
};

/// Precondition: ctx.n == ctx.obs.size() in {2, 3}, ctx.opt.magnitude_sigma > 0.
FewStarOutcome identifyFewStars(SearchContext& ctx, const WahbaSolver& solver);

/// The magnitude consistency of observations `obs_idx` as catalog stars `star_idx` (item 1
/// above): chi2 with the zero point fitted, divided by sigma_m^2.
double magnitudeChi2(const std::vector<StarObservation>& obs, const StarDatabase& db,
                     const int* obs_idx, const uint32_t* star_idx, int n, double sigma_m);

}  // namespace st::identify_detail

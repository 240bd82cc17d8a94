/// @file verify.hpp
/// Verification of an attitude hypothesis, shared by every identification algorithm and by
/// tracking: predict every catalog star in the field of view, match the observations to
/// them (mutual nearest neighbour inside an n-sigma gate), refine the attitude with a Wahba
/// solver over all matches, and compute the probability that the match is a coincidence.
///
/// False-match model (documented here once; DESIGN.md "identify").
///   Null hypothesis H0: the attitude is wrong, so the observations not used to build it fall
///   on the sky independently of the catalog stars. Observation k is then "matched" by
///   chance with probability p_k = N_fov * pi * r_k^2 / Omega_fov (N_fov catalog stars
///   predicted in the image of solid angle Omega_fov, gate radius r_k). With n observations
///   besides the `free` ones that any attitude fits by construction (two stars fix an
///   attitude), the number of chance matches X is Poisson-binomial; we use Binomial(n, p)
///   with the mean p of the p_k, whose upper tail bounds the Poisson-binomial one above the
///   mean (Hoeffding 1956), and a hypothesis with m matches besides those has
///       P(X >= m) = sum_{x >= m} C(n, x) p^x (1 - p)^(n - x).
///   A search that examined A candidate attitudes could meet such a coincidence A times, so
///   the reported probability is the union bound  P_false = min(1, A * P(X >= m)).
///   A hypothesis is accepted only when P_false <= false_match_threshold (default 1e-9).
///   The probability is computed on the final match set of the refined attitude.
///
/// Residual test (after the final refinement). With the right identities and honest centroid
/// covariances, 2 * loss = sum_k |b_k - R^T r_k|^2 / sigma_k^2 is chi-square with 2n - 3
/// degrees of freedom (wahba.hpp). When its upper tail is below residual_alpha, the match
/// set holds an outlier (a wrong pairing, or a star displaced beyond its covariance): the
/// observation with the largest normalised residual is excluded, the match is redone from
/// the re-solved attitude, and the test repeated while more than min_matches stars remain.
/// A set that still fails is rejected: a "solved" attitude must be covered by its covariance.
/// So is one that needed more than max(2, max_outlier_fraction * kept) exclusions: peeling
/// can carve a consistent subset out of any bad match, honest frames have few outliers.
///
/// Near-miss test (match-count consistency). A partial match (an attitude a few arcminutes
/// off in roll that fits the stars near the boresight) leaves unmatched observations lying
/// just outside their gates next to unmatched predicted stars. Under the right attitude an
/// unmatched observation (a false star, a star missing from the catalog) has an unmatched
/// predicted star within near_miss_factor gate radii only by chance, with probability
/// p_k = N_fov * pi * (f r_k)^2 / Omega_fov; the count of near misses X is bounded by
/// Binomial(n_unmatched, mean p_k), and the hypothesis is rejected when P(X >= x) <
/// residual_alpha.
#pragma once
#include <string>
#include <vector>

#include "catalog/star_database.hpp"
#include "common/chi_square.hpp"
#include "sensors/attitude/wahba.hpp"
#include "sensors/camera/camera_model.hpp"
#include "sensors/identify/star_match.hpp"
#include "sensors/identify/star_observation.hpp"

namespace st {

struct VerifyOptions {
  double gate_sigma = 5.0;      ///< gate radius in combined 1-sigma (observation + attitude)
  double min_gate_px = 0.0;     ///< lower bound of the gate radius [px]
  double scale_tolerance = 0;   ///< relative focal-length uncertainty: the gate grows by
                                ///< scale_tolerance * (angle from the boresight)
  double false_match_threshold = 1e-9;
  int min_matches = 4;          ///< fewer matched stars (seeds included) -> rejected
  int refine_iterations = 3;    ///< match / re-solve rounds
  double edge_margin_px = 0.0;  ///< predicted stars this close to the border are ignored
  bool enabled = true;          ///< false accepts every hypothesis (only for tests' teeth)
  bool residual_test = true;    ///< chi-square test of the final residuals, outlier removal
  bool near_miss_test = true;   ///< reject partial matches (unmatched stars just outside gates)
  double residual_alpha = 1e-4; ///< false-alarm probability of either test per hypothesis
  double near_miss_factor = 4.0;///< near-miss radius in gate radii
  double max_outlier_fraction = 0.25;  ///< more outliers removed than this fraction of the
                                       ///< kept matches (and more than 2) -> rejected

  /// True when all values are usable; otherwise false with `why` naming the field.
  bool isValid(std::string* why = nullptr) const;
};

struct VerificationResult {
  bool accepted = false;
  std::string reason;           ///< why it was rejected (empty when accepted)
  Quat q_ic = Quat::Identity();   ///< camera attitude, v_i = R(q_ic) v_cam
  Mat3 cov_cam = Mat3::Zero();    ///< [rad^2] camera frame
  std::vector<StarMatch> matches;  ///< sorted by observation index
  double false_match_probability = 1.0;
  double rms_residual = 0;      ///< [rad]
  double rms_residual_px = 0;   ///< [px]
  int predicted_in_fov = 0;     ///< catalog stars predicted in the image
  double chi2 = 0;              ///< 2 * Wahba loss of the final match set (weights 1/sigma^2)
  int outliers_removed = 0;     ///< observations excluded by the residual test
  int near_misses = 0;          ///< unmatched observations next to an unmatched prediction
};

class Verifier {
 public:
  /// Keeps references: database, camera and solver must outlive the verifier.
  Verifier(const StarDatabase& db, const CameraModel& camera, const WahbaSolver& solver,
           VerifyOptions options = {});

  /// Verifies the hypothesis "observation seeds[k].obs_index is star seeds[k].star_index".
  /// `attitudes_examined` is A in the false-match model (>= 1).
  VerificationResult verifySeeds(const std::vector<StarObservation>& obs,
                                 const std::vector<StarMatch>& seeds,
                                 double attitudes_examined) const;

  const VerifyOptions& options() const { return options_; }

 private:
  VerificationResult refine(const std::vector<StarObservation>& obs, Quat q_ic, Mat3 cov_cam,
                            double attitudes_examined, int free_matches) const;

  const StarDatabase& db_;
  const CameraModel& camera_;
  const WahbaSolver& solver_;
  VerifyOptions options_;
  double omega_fov_;            ///< solid angle of the image [sr]
  double cone_radius_;          ///< cone that holds the image [rad]
};

/// Upper tail of the binomial distribution P(X >= m), X ~ Binomial(n, p).
double binomialUpperTail(int n, int m, double p);

}  // namespace st

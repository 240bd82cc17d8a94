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
#pragma once
#include <string>
#include <vector>

#include "catalog/star_database.hpp"
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
};

struct VerificationResult {
  bool accepted = false;
  std::string reason;           ///< why it was rejected (empty when accepted)
  Quat q_ib = Quat::Identity();
  Mat3 cov_body = Mat3::Zero();
  std::vector<StarMatch> matches;  ///< sorted by observation index
  double false_match_probability = 1.0;
  double rms_residual = 0;      ///< [rad]
  double rms_residual_px = 0;   ///< [px]
  int predicted_in_fov = 0;     ///< catalog stars predicted in the image
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

  /// Verifies a prior attitude (e.g. a propagated one while tracking) with its body-frame
  /// covariance; `free_matches` observations are treated as fitted by construction (0 for an
  /// independent prior).
  VerificationResult verifyAttitude(const std::vector<StarObservation>& obs, const Quat& q_ib,
                                    const Mat3& cov_body, double attitudes_examined,
                                    int free_matches = 0) const;

  const VerifyOptions& options() const { return options_; }

 private:
  VerificationResult refine(const std::vector<StarObservation>& obs, Quat q_ib, Mat3 cov_body,
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

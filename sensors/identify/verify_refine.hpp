/// @file verify_refine.hpp
/// Internal to verify.cpp: one run of Verifier::refine. The match / re-solve / outlier /
/// near-miss rounds share their state (predictions, gates, exclusions, the current
/// solution), so it lives in one object instead of locals captured by many lambdas.
/// The models are documented in verify.hpp.
#pragma once
#include <utility>
#include <vector>

#include "sensors/attitude/drop_worst.hpp"
#include "sensors/identify/verify.hpp"

namespace st {

/// What a refinement reads from its Verifier (all references outlive the refinement).
struct VerifierParts {
  const StarDatabase& db;
  const CameraModel& camera;
  const WahbaSolver& solver;
  const VerifyOptions& options;
  double omega_fov;    ///< solid angle of the image [sr]
  double cone_radius;  ///< cone that holds the image [rad]
};

class VerifyRefinement {
 public:
  VerifyRefinement(const VerifierParts& parts, const std::vector<StarObservation>& obs,
                   Quat q_ic, Mat3 cov_cam);

  /// Runs the rounds and judges the final match set (false-match model in verify.hpp).
  VerificationResult run(double attitudes_examined, int free_matches);

 private:
  struct Predicted {
    uint32_t star;
    Vec3 v_c;        // predicted direction, camera frame
    double var_att;  // [rad^2] per-axis variance of the direction from the attitude covariance
  };

  void iterate();
  void refitUntilStable();
  void match();
  void predictInField();
  void nearestAndGates();
  void keepUnambiguous();
  void keepForced();
  bool passesResidualTest(int& dropped);
  DropWorstVerdict judgeResiduals();
  bool absorbNearMisses();
  int findNearMisses();
  bool uniqueNearMiss(int k, int j, double cos_r) const;
  WahbaSolution solveMatches(const std::vector<std::pair<int, int>>& extra) const;
  StarMatch makeMatch(int k, uint32_t star) const;
  void measureResiduals();
  double falseMatchProbability(double attitudes_examined, int free_matches) const;
  void decide(double near_tail);

  const VerifierParts p_;
  const VerifyOptions& opt_;
  const std::vector<StarObservation>& obs_;
  const std::vector<Star>& stars_;
  const int n_obs_;
  const double min_gate_;
  // With scale slack (FOV search candidates) the residuals hold a scale error the centroid
  // covariances do not describe; such candidates are re-verified after the focal-length fit.
  const bool residual_test_;
  const bool near_test_;

  VerificationResult res_;
  WahbaSolution sol_;
  std::vector<uint32_t> cone_;
  std::vector<Predicted> pred_;
  std::vector<StarMatch> matches_;
  std::vector<int> best_pred_, best_obs_;
  std::vector<double> gate_cos_, gate_rad_, best_dot_;
  std::vector<char> excluded_, ambiguous_;
  std::vector<int> forced_;  // near misses kept as matches: star per observation
  // Near misses: (observation, prediction) pairs, the unmatched observations counted, and
  // the mean chance probability of a near miss (model in verify.hpp).
  std::vector<std::pair<int, int>> near_;
  int n_unmatched_ = 0;
  double near_p_ = 0;
  int guard_ = 0, guard_limit_ = 0;
  bool residual_failed_ = false, settled_ = false;
};

}  // namespace st

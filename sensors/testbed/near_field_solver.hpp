/// @file near_field_solver.hpp
/// The iterative attitude estimation of seed 001 sec. IV.B on the near-field display: from
/// an attitude prediction, the near-field vectors R_0 + alpha_i b_i (alpha_i from the
/// prediction, eq. 56) -> master-star angle match against the display database within
/// +-tolerance -> Wahba (QUEST by default, any registered solver) -> the estimate becomes the
/// next prediction -> repeat. Every pass ("update" in the seed's Table 5) is reported.
#pragma once
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "common/conventions.hpp"
#include "sensors/attitude/wahba.hpp"
#include "sensors/testbed/display_geometry.hpp"
#include "sensors/testbed/master_angle_match.hpp"

namespace st::testbed {

struct NearFieldOptions {
  /// [rad] half-width of the angle window: the seed's "500 arc-second matching accuracy" is
  /// +-250" per angle (sec. V.A).
  double tolerance = arcsec2rad(250.0);
  int iterations = 1;         ///< passes (the seed's "updates", 1..5 in Table 5)
  std::string solver = WahbaSolver::defaultName();  ///< Wahba solver (sensors/attitude/registry.cpp)
  double sigma = 1e-4;        ///< [rad] per-star 1-sigma handed to the solver (weights, cov)
  int min_stars = 3;          ///< fewer matched stars: this pass keeps the prediction
  /// False and *why (naming the field) when invalid.
  bool isValid(std::string* why = nullptr) const;
};

struct NearFieldPass {
  bool ok = false;            ///< an attitude was estimated in this pass
  std::string reason;         ///< why not
  int stars_matched = 0;      ///< master included; 0 when no master was identified
  int angles_unique = 0, angles_ambiguous = 0;
  std::vector<std::pair<int, int>> matches;  ///< (observation, display star)
  Quat q_ib = Quat::Identity();  ///< the estimate (the prediction when !ok)
  Mat3 cov_body = Mat3::Zero();  ///< from the Wahba solver (zero when !ok)
};

struct NearFieldResult {
  std::vector<NearFieldPass> passes;
  bool ok() const;      ///< the last pass estimated an attitude
  Quat q_ib() const;    ///< the last estimate (the prediction if none)
};

class NearFieldSolver {
 public:
  /// Throws InputError naming the field on invalid geometry or options.
  NearFieldSolver(const DisplayGeometry& geometry, std::vector<Vec3> display_stars_I,
                  const NearFieldOptions& options);
  /// `b_cam`: measured unit vectors in the camera (= body) frame, brightest first.
  NearFieldResult solve(const std::vector<Vec3>& b_cam, const Quat& q_ib_predicted) const;
  /// The vectors one pass matches: the near-field vectors for the prediction (eq. 54). An
  /// entry is nullopt when its ray misses the screen plane at the predicted attitude.
  std::vector<std::optional<Vec3>> nearFieldVectors(const std::vector<Vec3>& b_cam,
                                                    const Quat& q_ib_predicted) const;
  const AngleDatabase& database() const { return db_; }
  const DisplayGeometry& geometry() const { return geometry_; }

 private:
  NearFieldPass pass(const std::vector<Vec3>& b_cam, const Quat& q_pred) const;
  DisplayGeometry geometry_;
  AngleDatabase db_;
  NearFieldOptions options_;
  std::unique_ptr<WahbaSolver> solver_;
};

/// The display stars' database vectors (eq. 57/58) from their screen pixels.
std::vector<Vec3> displayDatabase(const DisplayGeometry& g, const std::vector<Vec2>& screen_px);

}  // namespace st::testbed

/// @file recursive_id.hpp
/// Recursive star identification (seed 002): with an attitude prediction no pattern search is
/// needed. The catalog stars the prediction puts in the image are projected, each gets a
/// small window, and the centroid found in a window is that star when it passes a gate.
///   1. cone query of the catalog around the predicted boresight (FOV + 3 sigma of the
///      attitude), projection into the camera (pinhole + distortion); stars entering the FOV
///      are picked up by the same projection;
///   2. a window per predicted star (brightest first, away from the border and from blends),
///      sized from the attitude covariance projected into pixels (H P H^T,
///      H = d(pixel)/d(dtheta)) and the blur (rate x exposure) (seed 004 §4.2.3 predictive
///      centroiding); `centroidWindows` reads only those pixels;
///   3. Mahalanobis gate per star: d^T (H P H^T + C)^-1 d <= gate_sigma^2, C the centroid's
///      covariance with its floor (eigenvalues at least centroid_sigma_px^2) plus the camera
///      model's error. With both covariances sigma^2 I this is |d| <= 3 sqrt(2) sigma (seed 002
///      step 5) for the default gate_sigma = 3. (The floor is a least sigma, not a third term:
///      issue 38's D3.)
///
/// Frames: the prediction and everything here are in the camera frame (q_ic, cov_cam,
/// rate_cam). Keeps scratch buffers between frames (no allocation once warm): one per thread.
#pragma once
#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

#include "catalog/star_database.hpp"
#include "common/attitude.hpp"
#include "sensors/camera/camera_model.hpp"
#include "sensors/camera/jacobians.hpp"
#include "sensors/detect/centroid.hpp"
#include "sensors/detect/detector_options.hpp"
#include "sensors/detect/star_detector.hpp"

namespace st {

struct RecursiveIdOptions {
  int max_stars = 20;              ///< windows per frame (brightest predicted stars)
  int min_stars = 4;               ///< fewer predicted / gated stars -> failure
  bool drop_saturated = true;      ///< leave saturated stars out while min_stars others remain
  double gate_sigma = 3.0;         ///< Mahalanobis gate
  double edge_margin_px = 4.0;     ///< predicted stars closer to the border are not windowed
  double blend_separation_px = 5.0;///< nor those closer than this to another catalog star
  /// nor those whose centroid a star of the database's blend screen (fainter than its limit,
  /// StarDatabase::screenStars) would pull by more than this many centroid sigmas
  double screen_pull_sigma = 1.0;
  double centroid_sigma_px = 0.1;  ///< [px] floor of a centroid's sigma in windows and gate
  double exposure_s = 0.1;         ///< [s] for the blur of predicted stars
  DetectorOptions detect;          ///< window centroiding
};

/// A camera-frame attitude prediction.
struct CameraPrediction {
  Quat q_ic = Quat::Identity();
  Mat3 cov_cam = Mat3::Identity();  ///< [rad^2]
  Vec3 rate_cam = Vec3::Zero();     ///< [rad/s] for the blur
};

struct RecursiveIdResult {
  enum class Status : uint8_t { kOk, kTooFewPredicted, kTooFewInGate };
  Status status = Status::kTooFewPredicted;
  int windows = 0;                  ///< predicted stars given a window
  int with_centroid = 0;            ///< windows where a centroid was found
  std::vector<Centroid> stars;      ///< gated centroids
  std::vector<uint32_t> star_index; ///< their database stars
  double identify_s = 0, detect_s = 0;  ///< [s] wall time: prediction + gate, windows
};

class RecursiveIdentifier {
 public:
  /// Keeps references: the database and camera must outlive it.
  RecursiveIdentifier(const StarDatabase& db, const CameraModel& camera, RecursiveIdOptions o);

  /// Identifies the stars of `image` under `pred`; `out` is the caller's, reused per frame.
  void identify(const cv::Mat& image, const CameraPrediction& pred, RecursiveIdResult& out);

  const RecursiveIdOptions& options() const { return opts_; }

  /// The camera it references was changed (refined online) and the camera-model error term
  /// [px] in force, added in quadrature to the centroid sigma of the windows and the gate.
  void cameraChanged(double model_error_px);

 private:
  struct Candidate {
    uint32_t star_index;
    Vec3 v_cam;                     // predicted direction
    Vec2 px;                        // predicted pixel
    Mat23 H = Mat23::Zero();        // d(px)/d(dtheta_cam)
    Mat2 cov_att_px = Mat2::Zero(); // H P H^T
  };
  void predictCandidates(const CameraPrediction& pred);
  void placeWindows(const CameraPrediction& pred);
  void gate(RecursiveIdResult& out);
  /// C of the gate: `cov_px` floored at centroid_sigma_px^2, plus the model error's variance.
  Mat2 centroidCovariance(const Mat2& cov_px) const;
  bool blended(const Candidate& c, const Vec2& blur) const;
  bool screenedOut(const Candidate& c, double reach_x, double reach_y) const;

  const StarDatabase& db_;
  const CameraModel& camera_;
  RecursiveIdOptions opts_;
  StarDetector detector_;  // built once: the windows are centroided without validation
  double half_diagonal_fov_;
  double sigma_c_px_;  // centroid_sigma_px (+) the camera-model error term: the windows' sigma
  double model_error_px_ = 0;  // the camera-model error term in force
  std::vector<uint32_t> cone_;
  std::vector<Candidate> candidates_;
  struct ScreenImage {
    Vec2 px;
    double flux;  // relative, 10^(-0.4 V)
  };
  std::vector<ScreenImage> screen_;  // the blend-screen stars predicted in the image
  std::vector<PredictedStar> windows_;
  std::vector<const Candidate*> windowed_;
  std::vector<WindowResult> found_;
  std::vector<double> gated_d2_;
};

}  // namespace st

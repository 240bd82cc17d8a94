/// @file online_camera.hpp
/// The star tracker's camera model refined online from its own verified fixes (issue 19):
/// every verified frame's identified stars are gathered; every `frames_per_fit` of them the
/// one camera-model fit (sensors/camera/camera_fit.hpp) estimates focal length and k1 (not
/// the principal point: online_camera.cpp says why) with the previous posterior as its prior (a recursive information filter whose
/// first prior is the camera file), and the stars' residuals give the camera-model error
/// term: the pixel sigma, beyond centroid noise, that the model leaves unexplained. Both are
/// carried to the next frames (identification gates and fix covariances).
///
/// The information is multiplied by `forgetting` before each fit, so a lens that drifts
/// (temperature) is followed with a memory of about 1 / (1 - forgetting) fits.
///
/// Cost: a fit over 10 frames costs about as much as tracking 40 frames. While the fits
/// find no significant model error, the interval between them doubles (fitting the last
/// `frames_per_fit` verified frames before each), up to 64 x frames_per_fit; a fit that finds
/// one goes back to every `frames_per_fit` frames.
#pragma once
#include <optional>
#include <vector>

#include "sensors/camera/camera_fit.hpp"

namespace st {

struct OnlineCameraOptions {
  bool enabled = true;
  int frames_per_fit = 10;        ///< verified frames gathered per fit
  double forgetting = 0.95;       ///< information kept from one fit to the next
  /// The camera file's 1-sigma: relative focal length, k1.
  double prior_focal_rel = 0.02, prior_k1 = 0.2;
  /// Largest camera-model error term [px] carried: beyond it the model, not its error bar,
  /// is wrong (a wrong match's scatter is larger).
  double max_model_error_px = 1.0;
};

/// One fit's outcome, for the caller's record.
struct OnlineCameraUpdate {
  CameraFitResult fit;
  double model_error_px = 0;
};

class OnlineCamera {
 public:
  OnlineCamera(const CameraModel& file_camera, OnlineCameraOptions options);
  /// Verified frames from one fit to the next (frames_per_fit, doubling while the model
  /// explains the residuals).
  int interval() const { return interval_; }

  /// A verified frame's stars; returns the update when this frame completes a batch and the
  /// fit succeeded (the caller adopts fit.camera and model_error_px).
  std::optional<OnlineCameraUpdate> addVerifiedFrame(const CameraModel& current,
                                                     FrameStars stars);

  /// A refined camera found elsewhere (lost-in-space healing a bad file): its fit becomes the
  /// prior of the next online fit.
  void adopt(const CameraFitResult& fit);

  /// Forget the gathered frames (not the prior): after a re-initialisation.
  void clearPending() {
    pending_.clear();
    since_fit_ = 0;
  }

  const CameraModel& fileCamera() const { return file_; }
  const std::optional<CameraFitResult>& lastFit() const { return last_; }

 private:
  CameraModel file_;
  OnlineCameraOptions opts_;
  CameraPrior prior_;
  std::vector<FrameStars> pending_;
  std::optional<CameraFitResult> last_;
  static constexpr int kMaxIntervalFits = 64;
  int interval_ = 0;    // verified frames from one fit to the next (set from the options)
  int since_fit_ = 0;   // verified frames since the last fit
};

/// The camera-model error term of a fit: modelErrorSigmaPx when the residuals' chi-square
/// exceeds its 99.9 % point for the fit's dof (centroid noise alone explains anything
/// below), else 0; capped at `max_px`.
double significantModelErrorPx(const CameraFitResult& fit, const std::vector<FrameStars>& frames,
                               double max_px);

}  // namespace st

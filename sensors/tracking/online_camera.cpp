#include "sensors/tracking/online_camera.hpp"

#include <algorithm>

#include "common/chi_square.hpp"

namespace st {

double significantModelErrorPx(const CameraFitResult& fit, const std::vector<FrameStars>& frames,
                               double max_px) {
  if (!fit.ok || fit.dof <= 0) return 0.0;
  if (fit.chi2 <= chiSquareQuantile(0.999, fit.dof)) return 0.0;
  return std::min(max_px, modelErrorSigmaPx(fit, frames));
}

OnlineCamera::OnlineCamera(const CameraModel& file_camera, OnlineCameraOptions options)
    : file_(file_camera),
      opts_(options),
      prior_(CameraPrior::around(file_camera, options.prior_focal_rel, 0, options.prior_k1)),
      interval_(options.frames_per_fit) {
  // k2 stays the file's: one term is what a few frames of a narrow field determine.
  prior_.information(kK2, kK2) = 0;
}

void OnlineCamera::adopt(const CameraFitResult& fit) {
  if (!fit.ok) return;
  const CameraPrior p = fit.posterior();
  // The parameters that fit left fixed keep this prior's information about them.
  for (int i = 0; i < kNumCameraParams; ++i) {
    if (p.information(i, i) <= 0) continue;
    prior_.mean[i] = p.mean[i];
    for (int j = 0; j < kNumCameraParams; ++j)
      if (p.information(j, j) > 0) prior_.information(i, j) = p.information(i, j);
  }
  prior_.information.row(kK2).setZero();
  prior_.information.col(kK2).setZero();
  last_ = fit;
}

std::optional<OnlineCameraUpdate> OnlineCamera::addVerifiedFrame(const CameraModel& current,
                                                                 FrameStars stars) {
  if (!opts_.enabled || stars.size() < 3) return std::nullopt;
  // Only the last frames_per_fit verified frames before a fit are gathered.
  if (++since_fit_ <= interval_ - opts_.frames_per_fit) return std::nullopt;
  pending_.push_back(std::move(stars));
  if (static_cast<int>(pending_.size()) < opts_.frames_per_fit) return std::nullopt;
  since_fit_ = 0;
  CameraFitSpec spec;
  spec.focal = true;
  // Not the principal point: a shift of it is, to first order, a rotation of the camera in
  // the body -- the stars see the same thing as a mounting change, so its fit wanders within
  // its large uncertainty and drags every attitude with it (measured: fitting it made the
  // fixes' NEES ~5000 on a perfect simulated camera). It belongs to the mounting calibration
  // (R_body_cam), done against the body's reference, not to the sky.
  spec.principal_point = false;
  spec.radial_terms = 1;
  CameraPrior prior = prior_;
  prior.information *= opts_.forgetting;
  CameraFitOptions fo;
  fo.outlier_sigma = 5;  // a wrong match or a blend must not bend the lens
  // The fit starts from the camera in use; k2 keeps its value (free only in calibrate).
  CameraFitResult fit = fitCamera(current, pending_, spec, &prior, fo);
  std::optional<OnlineCameraUpdate> out;
  if (fit.ok) {
    const double model_px = significantModelErrorPx(fit, pending_, opts_.max_model_error_px);
    // A model that explains the residuals is refitted ever more rarely (a lens changes
    // slowly; each fit costs ~10 frames' tracking); one that does not, at the full rate.
    interval_ = model_px > 0 ? opts_.frames_per_fit
                             : std::min(2 * interval_, kMaxIntervalFits * opts_.frames_per_fit);
    prior_ = fit.posterior();
    last_ = fit;
    out = OnlineCameraUpdate{std::move(fit), model_px};
  }
  pending_.clear();
  return out;
}

}  // namespace st

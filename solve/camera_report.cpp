#include "solve/camera_report.hpp"

#include <cstdio>

#include "common/conventions.hpp"

namespace st::solve {

namespace {
const char* cameraSource(const SolveReport& r) {
  if (!r.o.camera.camera_file.empty())
    return r.ps.search.healed ? "camera file, refined from the stars" : "camera file";
  return r.o.camera.given() ? "--fov-deg, refined from the stars" : "fitted from the stars";
}
}  // namespace

std::string cameraDiscrepancy(const SolveReport& r) {
  const auto& fit = r.ps.search.camera_fit;
  if (r.o.camera.camera_file.empty() || !fit) return "";
  const std::string d =
      describeDiscrepancy(*fit, r.o.camera.resolve(r.in.width, r.in.height), r.o.camera.camera_file);
  return d.empty() ? d : d + "; run `startracker calibrate` on frames of this camera";
}

nlohmann::ordered_json cameraJson(const SolveReport& r) {
  const CameraModel& cam = r.ps.search.camera;
  nlohmann::ordered_json j = {{"fx", cam.fx()}, {"fy", cam.fy()}, {"cx", cam.cx()},
                              {"cy", cam.cy()}, {"k1", cam.distortion().k1},
                              {"k2", cam.distortion().k2}, {"source", cameraSource(r)},
                              {"model_error_px", r.ps.search.model_error_px}};
  if (const auto& fit = r.ps.search.camera_fit) {
    j["fit"] = {{"fx", fit->theta[kFx]},
                {"fx_sigma", fit->sigma(kFx)},
                {"k1", fit->theta[kK1]},
                {"k1_sigma", fit->sigma(kK1)},
                {"k2", fit->theta[kK2]},
                {"k2_sigma", fit->sigma(kK2)},
                {"radial_terms", fit->spec.radial_terms},
                {"rms_before_px", fit->rms_before_px},
                {"rms_after_px", fit->rms_after_px},
                {"chi2", fit->chi2},
                {"dof", fit->dof}};
  }
  j["discrepancy"] = cameraDiscrepancy(r);
  return j;
}

void printCameraFitText(const SolveReport& r) {
  const auto& fit = r.ps.search.camera_fit;
  if (!fit) return;
  const double hfov = fit->camera.horizontalFov();
  // d(HFOV)/d(f) = -HFOV-ish: 2 atan(w / 2f) -> -(w / f) / (1 + (w / 2f)^2) / f.
  const double half = 0.5 * r.in.width / fit->theta[kFx];
  const double hfov_sigma = 2 * half / (1 + half * half) * fit->sigma(kFx) / fit->theta[kFx];
  std::printf("camera fit focal %.2f +- %.2f px (HFOV %.4f +- %.4f deg)", fit->theta[kFx],
              fit->sigma(kFx), rad2deg(hfov), rad2deg(hfov_sigma));
  if (fit->spec.radial_terms >= 1)
    std::printf(", k1 %.4g +- %.2g", fit->theta[kK1], fit->sigma(kK1));
  if (fit->spec.radial_terms >= 2)
    std::printf(", k2 %.4g +- %.2g", fit->theta[kK2], fit->sigma(kK2));
  if (fit->spec.radial_terms == 0) std::printf(", no distortion term supported by the stars");
  std::printf("; residual %.3f -> %.3f px; model error %.3f px\n", fit->rms_before_px,
              fit->rms_after_px, r.ps.search.model_error_px);
}

}  // namespace st::solve

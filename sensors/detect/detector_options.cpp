#include "sensors/detect/detector_options.hpp"

#include <algorithm>
#include <sstream>

#include "sensors/detect/centroider.hpp"
#include "sensors/detect/prefilter.hpp"

namespace st {

bool DetectorOptions::isValid(std::string* error) const {
  std::ostringstream e;
  auto bad = [&](const char* key, double v, const char* want) {
    e << "DetectorOptions." << key << " = " << v << ": " << want;
  };
  const auto pf = prefilterNames();
  std::string cerr;
  if (!(gain_e_per_adu > 0))
    bad("gain_e_per_adu", gain_e_per_adu, "must be > 0");
  else if (!(read_noise_adu >= 0))
    bad("read_noise_adu", read_noise_adu, "must be >= 0");
  else if (!(saturation_adu >= 0))
    bad("saturation_adu", saturation_adu, "must be >= 0 (0 = type maximum)");
  else if (!(threshold_sigma > 0))
    bad("threshold_sigma", threshold_sigma, "must be > 0");
  else if (threshold_mode != "fixed" && threshold_mode != "dynamic")
    e << "DetectorOptions.threshold_mode = '" << threshold_mode << "': valid fixed, dynamic";
  else if (dynamic_target_stars < 1)
    bad("dynamic_target_stars", dynamic_target_stars, "must be >= 1");
  else if (!(dynamic_min_sigma > 0))
    bad("dynamic_min_sigma", dynamic_min_sigma, "must be > 0");
  else if (!(dynamic_max_sigma >= dynamic_min_sigma))
    bad("dynamic_max_sigma", dynamic_max_sigma, "must be >= dynamic_min_sigma");
  else if (!(dynamic_step_sigma > 0))
    bad("dynamic_step_sigma", dynamic_step_sigma, "must be > 0");
  else if (background_tile_px < 0 || (background_tile_px > 0 && background_tile_px < 16))
    bad("background_tile_px", background_tile_px, "must be 0 (global) or >= 16");
  else if (background_samples < 16)
    bad("background_samples", background_samples, "must be >= 16");
  else if (std::find(pf.begin(), pf.end(), prefilter) == pf.end())
    e << "DetectorOptions.prefilter = '" << prefilter << "': valid none, neighbourhood, grid";
  else if (prefilter_min_count < 1 || prefilter_min_count > 25)
    bad("prefilter_min_count", prefilter_min_count, "must be in [1, 25]");
  else if (min_area < 1)
    bad("min_area", min_area, "must be >= 1");
  else if (max_area < min_area)
    bad("max_area", max_area, "must be >= min_area");
  else if (max_stars < 1)
    bad("max_stars", max_stars, "must be >= 1");
  else if (!(min_separation_px >= 0))
    bad("min_separation_px", min_separation_px, "must be >= 0");
  else if (!(max_elongation >= 1))
    bad("max_elongation", max_elongation, "must be >= 1");
  else if (!(pixel_aspect >= 0.125 && pixel_aspect <= 8))
    bad("pixel_aspect", pixel_aspect, "must be in [0.125, 8]");
  else if (!(max_psf_sigma_px > 0))
    bad("max_psf_sigma_px", max_psf_sigma_px, "must be > 0");
  else if (!(hot_pixel_fraction > 0 && hot_pixel_fraction <= 1))
    bad("hot_pixel_fraction", hot_pixel_fraction, "must be in (0, 1]");
  else if (!Centroider::create(centroider, &cerr))
    e << "DetectorOptions.centroider: " << cerr;
  else if (!(psf_sigma_px >= 0 && psf_sigma_px < 50))
    bad("psf_sigma_px", psf_sigma_px, "must be in [0, 50) (0 = estimate)");
  else if (window_margin_px < 0 || window_margin_px > 20)
    bad("window_margin_px", window_margin_px, "must be in [0, 20]");
  else if (!(window_sigmas > 0))
    bad("window_sigmas", window_sigmas, "must be > 0");
  else if (max_window_half_px < 2)
    bad("max_window_half_px", max_window_half_px, "must be >= 2");
  const std::string msg = e.str();
  if (error) *error = msg;
  return msg.empty();
}

}  // namespace st

#include "navigation/run_summary.hpp"

#include <algorithm>
#include <cmath>

#include "common/conventions.hpp"
#include "fusion/consistency.hpp"

namespace st {

namespace {

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const std::size_t i = std::min(v.size() - 1, std::size_t(std::ceil(p * double(v.size())) - 1));
  return v[i];
}
double rms(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x * x;
  return v.empty() ? 0 : std::sqrt(s / double(v.size()));
}

}  // namespace

void printNavigationSummary(const std::vector<NavStep>& steps, std::FILE* out) {
  // A run without a filter (no gyro: FusionOptions::filter_enabled false) has no step with a
  // filter state; its output is the raw fixes, scored in the filter's place.
  const bool filtered =
      std::any_of(steps.begin(), steps.end(), [](const NavStep& s) { return s.initialized; });
  long matched_with_truth = 0, misidentified = 0, blend_claims = 0, unscored = 0;
  std::vector<double> cross, roll, nees, fix_err, filt_err, fix_nees, unfiltered_err;
  for (const NavStep& s : steps) {
    // Fixes of a filtered run made while the filter held no state (suspended: gyro lost).
    if (filtered && s.has_truth && s.fix && !s.initialized)
      unfiltered_err.push_back(rad2arcsec(s.fix_error.total));
    if (filtered && s.has_truth && s.initialized) {
      cross.push_back(rad2arcsec(s.error.cross_boresight));
      roll.push_back(std::abs(rad2arcsec(s.error.roll)));
      nees.push_back(s.nees);
      if (s.fix) {
        fix_err.push_back(rad2arcsec(s.fix_error.total));
        filt_err.push_back(rad2arcsec(s.error.total));
        fix_nees.push_back(s.fix_nees);
      }
    }
    if (!filtered && s.has_truth && s.fix) {
      cross.push_back(rad2arcsec(s.fix_error.cross_boresight));
      roll.push_back(std::abs(rad2arcsec(s.fix_error.roll)));
      fix_err.push_back(rad2arcsec(s.fix_error.total));
      fix_nees.push_back(s.fix_nees);
    }
    if (s.has_truth && s.fix && !s.ids_scored) ++unscored;
    if (s.has_truth && s.fix && s.ids_scored) {
      matched_with_truth += s.stars_matched;
      misidentified += s.misidentified;
      blend_claims += s.blend_claims;
    }
  }
  if (cross.empty()) return;
  if (filtered) {
    std::fprintf(out, "attitude error vs GROUND_TRUTH (%zu steps) [arcsec]:\n", cross.size());
  } else {
    std::fprintf(out, "attitude error vs GROUND_TRUTH, raw fixes without a filter (%zu frames "
                 "with a fix) [arcsec]:\n", cross.size());
  }
  std::fprintf(out, "  cross-boresight  RMS %8.2f  95 %% %8.2f  max %8.2f\n", rms(cross),
              percentile(cross, 0.95), *std::max_element(cross.begin(), cross.end()));
  std::fprintf(out, "  roll             RMS %8.2f  95 %% %8.2f  max %8.2f\n", rms(roll),
              percentile(roll, 0.95), *std::max_element(roll.begin(), roll.end()));
  if (filtered && !fix_err.empty()) {
    std::fprintf(out, "  total, frames with a fix: filter RMS %.2f, raw fixes RMS %.2f\n",
                rms(filt_err), rms(fix_err));
  }
  if (!unfiltered_err.empty()) {
    std::fprintf(out, "  frames with a fix but no filter state (not in the lines above): %zu, raw "
                 "fixes RMS %.2f\n", unfiltered_err.size(), rms(unfiltered_err));
  }
  if (!filtered) {
    std::fprintf(out, "  total: raw fixes RMS %.2f\n", rms(fix_err));
    std::fprintf(out, "  filter: none (no filter NEES)\n");
  } else {
    const ChiSquareBand band = averagedChiSquareBand(3, int(nees.size()));
    double mean_nees = 0;
    for (double v : nees) mean_nees += v;
    mean_nees /= double(nees.size());
    std::fprintf(out, "  filter: mean NEES %.3f (3 dof; 95 %% band for independent steps [%.3f, %.3f]: "
                "%s; consecutive filter steps are correlated)\n",
                mean_nees, band.lo, band.hi, band.contains(mean_nees) ? "inside" : "outside");
    // The portable check of the filter's consistency (tests read this line): the fraction of
    // steps whose NEES lies below the chi2(3) median and 95 % point (0.5 and 0.95 when
    // consistent; successive steps are correlated through the filter).
    const double q50 = chiSquareQuantile(0.5, 3), q95f = chiSquareQuantile(0.95, 3);
    auto fraction = [&](double q) {
      return double(std::count_if(nees.begin(), nees.end(), [&](double v) { return v <= q; })) /
             double(nees.size());
    };
    std::fprintf(out, "  filter NEES: %.3f below the chi2(3) median, %.3f below its 95 %% point "
                 "(%zu steps)\n", fraction(q50), fraction(q95f), nees.size());
  }
  if (!fix_nees.empty()) {
    // Raw fixes are (nearly) independent frame to frame: the fraction of NEES values below
    // the chi2(3) 95 % point is the portable consistency check (0.95 when consistent).
    const double q95 = chiSquareQuantile(0.95, 3);
    const auto below = std::count_if(fix_nees.begin(), fix_nees.end(),
                                     [&](double v) { return v <= q95; });
    std::fprintf(out, "  raw fixes: median NEES %.3f (chi2(3) median 2.366), %.1f %% below the "
                "chi2(3) 95 %% point\n",
                percentile(fix_nees, 0.5), 100.0 * double(below) / double(fix_nees.size()));
  }
  if (matched_with_truth > 0) {
    std::fprintf(out, "  identification: %ld matched stars, %ld misidentified (claimed star not "
                "the true star nearest to the centroid), %ld named after the other member of "
                "an unresolved pair\n",
                matched_with_truth, misidentified, blend_claims);
  }
  if (unscored > 0)
    std::fprintf(out, "  identification: not scored on %ld frame(s) whose truth lists no stars\n",
                 unscored);
}

}  // namespace st

namespace st {

void printRateSummary(const std::vector<NavStep>& steps, std::FILE* out) {
  std::vector<double> ex, ey, ez, total, nees, fix_err;
  bool gyroless = false;
  for (const NavStep& s : steps) {
    if (!s.has_true_rate) continue;
    if (s.has_fix_rate) fix_err.push_back((s.fix_rate - s.rate_true).norm() * kDegPerRad);
    if (!s.initialized) continue;
    gyroless = gyroless || s.gyroless;
    const Vec3 e = s.rate_error * kDegPerRad;
    ex.push_back(e.x());
    ey.push_back(e.y());
    ez.push_back(e.z());
    total.push_back(e.norm());
    if (s.gyroless) nees.push_back(s.rate_nees);
  }
  if (total.empty() && fix_err.empty()) return;
  std::fprintf(out, "body rate vs GROUND_TRUTH (central differences of the true attitudes) "
               "[deg/s]:\n");
  if (!total.empty()) {
    std::fprintf(out, "  filter rate (%s) error RMS x %.5f y %.5f z %.5f total %.5f, max %.5f "
                 "(%zu steps)\n",
                 gyroless ? "gyroless state" : "gyro - bias", rms(ex), rms(ey), rms(ez),
                 rms(total), *std::max_element(total.begin(), total.end()), total.size());
  }
  if (!nees.empty()) {
    double mean = 0;
    for (double v : nees) mean += v;
    mean /= double(nees.size());
    const double q95 = chiSquareQuantile(0.95, 3);
    const auto below =
        std::count_if(nees.begin(), nees.end(), [&](double v) { return v <= q95; });
    std::fprintf(out, "  filter rate NEES: mean %.3f (3 dof), %.3f below the chi2(3) 95 %% "
                 "point\n", mean, double(below) / double(nees.size()));
  }
  if (!fix_err.empty()) {
    std::fprintf(out, "  tracker frame-to-frame rate error RMS %.5f (%zu frames; the mean over "
                 "the frame interval)\n", rms(fix_err), fix_err.size());
  }
}

}  // namespace st

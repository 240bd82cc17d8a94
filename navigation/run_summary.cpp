#include "navigation/run_summary.hpp"

#include <cmath>

#include "common/conventions.hpp"
#include "fusion/consistency.hpp"

namespace st {

namespace {
const double kQ50 = chiSquareQuantile(0.5, 3), kQ95 = chiSquareQuantile(0.95, 3);
}  // namespace

void RunSummary::Series::add(double v) {
  h.add(v);
  sum += v;
  sum_sq += v * v;
  below_q50 += v <= kQ50;
  below_q95 += v <= kQ95;
}

double RunSummary::Series::rms() const { return empty() ? 0 : std::sqrt(sum_sq / double(n())); }
double RunSummary::Series::mean() const { return empty() ? 0 : sum / double(n()); }

void RunSummary::add(const NavStep& s) {
  addRate(s);
  addHeads(s);
  filtered_ = filtered_ || s.initialized;
  // Scored as a filtered run: the filter's estimate at every step with truth, and the fixes
  // of the frames where the filter held no state (suspended: gyro lost) apart.
  if (s.has_truth && s.fix && !s.initialized) unfiltered_err_.add(rad2arcsec(s.fix_error.total));
  if (s.has_truth && s.initialized) {
    filt_.cross.add(rad2arcsec(s.error.cross_boresight));
    filt_.roll.add(std::abs(rad2arcsec(s.error.roll)));
    nees_.add(s.nees);
    if (s.fix) {
      filt_.fix_err.add(rad2arcsec(s.fix_error.total));
      filt_err_.add(rad2arcsec(s.error.total));
      filt_.fix_nees.add(s.fix_nees);
    }
  }
  // Scored as a run without a filter: its output is the raw fixes.
  if (s.has_truth && s.fix) {
    raw_.cross.add(rad2arcsec(s.fix_error.cross_boresight));
    raw_.roll.add(std::abs(rad2arcsec(s.fix_error.roll)));
    raw_.fix_err.add(rad2arcsec(s.fix_error.total));
    raw_.fix_nees.add(s.fix_nees);
  }
  if (s.has_truth && s.fix && !s.ids_scored) ++unscored_;
  if (s.has_truth && s.fix && s.ids_scored) {
    matched_with_truth_ += s.stars_matched;
    misidentified_ += s.misidentified;
    blend_claims_ += s.blend_claims;
  }
}

void RunSummary::print(std::FILE* out) const {
  const Scored& sc = filtered_ ? filt_ : raw_;
  if (sc.cross.empty()) return;
  if (filtered_) {
    std::fprintf(out, "attitude error vs GROUND_TRUTH (%llu steps) [arcsec]:\n",
                 static_cast<unsigned long long>(sc.cross.n()));
  } else {
    std::fprintf(out, "attitude error vs GROUND_TRUTH, raw fixes without a filter (%llu frames "
                 "with a fix) [arcsec]:\n", static_cast<unsigned long long>(sc.cross.n()));
  }
  std::fprintf(out, "  cross-boresight  RMS %8.2f  95 %% %8.2f  max %8.2f\n", sc.cross.rms(),
               sc.cross.h.quantile(0.95), sc.cross.h.max());
  std::fprintf(out, "  roll             RMS %8.2f  95 %% %8.2f  max %8.2f\n", sc.roll.rms(),
               sc.roll.h.quantile(0.95), sc.roll.h.max());
  if (filtered_ && !sc.fix_err.empty()) {
    std::fprintf(out, "  total, frames with a fix: filter RMS %.2f, raw fixes RMS %.2f\n",
                 filt_err_.rms(), sc.fix_err.rms());
  }
  if (filtered_ && !unfiltered_err_.empty()) {
    std::fprintf(out, "  frames with a fix but no filter state (not in the lines above): %llu, raw "
                 "fixes RMS %.2f\n", static_cast<unsigned long long>(unfiltered_err_.n()),
                 unfiltered_err_.rms());
  }
  if (!filtered_) {
    std::fprintf(out, "  total: raw fixes RMS %.2f\n", sc.fix_err.rms());
    std::fprintf(out, "  filter: none (no filter NEES)\n");
  } else {
    const ChiSquareBand band = averagedChiSquareBand(3, int(nees_.n()));
    const double mean_nees = nees_.mean();
    std::fprintf(out, "  filter: mean NEES %.3f (3 dof; 95 %% band for independent steps [%.3f, %.3f]: "
                 "%s; consecutive filter steps are correlated)\n",
                 mean_nees, band.lo, band.hi, band.contains(mean_nees) ? "inside" : "outside");
    // The portable check of the filter's consistency (tests read this line): the fraction of
    // steps whose NEES lies below the chi2(3) median and 95 % point (0.5 and 0.95 when
    // consistent; successive steps are correlated through the filter).
    const double n = double(nees_.n());
    std::fprintf(out, "  filter NEES: %.3f below the chi2(3) median, %.3f below its 95 %% point "
                 "(%llu steps)\n", double(nees_.below_q50) / n, double(nees_.below_q95) / n,
                 static_cast<unsigned long long>(nees_.n()));
  }
  if (!sc.fix_nees.empty()) {
    // Raw fixes are (nearly) independent frame to frame: the fraction of NEES values below
    // the chi2(3) 95 % point is the portable consistency check (0.95 when consistent).
    std::fprintf(out, "  raw fixes: median NEES %.3f (chi2(3) median 2.366), %.1f %% below the "
                 "chi2(3) 95 %% point\n", sc.fix_nees.h.quantile(0.5),
                 100.0 * double(sc.fix_nees.below_q95) / double(sc.fix_nees.n()));
  }
  if (matched_with_truth_ > 0) {
    std::fprintf(out, "  identification: %ld matched stars, %ld misidentified (claimed star not "
                 "the true star nearest to the centroid), %ld named after the other member of "
                 "an unresolved pair\n",
                 matched_with_truth_, misidentified_, blend_claims_);
  }
  if (unscored_ > 0)
    std::fprintf(out, "  identification: not scored on %ld frame(s) whose truth lists no stars\n",
                 unscored_);
  printHeads(out);
}

void RunSummary::addHeads(const NavStep& s) {
  if (s.heads.size() < 2 || !s.has_frame) return;
  if (heads_.size() < s.heads.size()) heads_.resize(s.heads.size());
  ++head_steps_;
  if (s.heads_dof > 0) {
    heads_chi2_.add(s.heads_chi2 / s.heads_dof);
    merged_ += s.heads_merged;
    disagreed_ += !s.heads_merged;
  }
  for (std::size_t h = 0; h < s.heads.size(); ++h) {
    const NavHead& nh = s.heads[h];
    HeadSeries& hs = heads_[h];
    hs.label = nh.label;
    ++hs.frames;
    hs.solved += nh.fix;
    hs.misidentified += nh.misidentified;
    if (nh.fix && s.has_truth) {
      hs.cross.add(rad2arcsec(nh.fix_error.cross_boresight));
      hs.roll.add(std::abs(rad2arcsec(nh.fix_error.roll)));
      hs.total.add(rad2arcsec(nh.fix_error.total));
    }
  }
  if (s.heads_merged && s.has_truth) {
    joint_cross_.add(rad2arcsec(s.fix_error.cross_boresight));
    joint_roll_.add(std::abs(rad2arcsec(s.fix_error.roll)));
    joint_total_.add(rad2arcsec(s.fix_error.total));
  }
}

void RunSummary::printHeads(std::FILE* out) const {
  if (heads_.empty()) return;
  std::fprintf(out, "camera heads: %zu, %llu frame steps; joint fixes %llu, heads disagreeing "
               "(not merged) %llu; disagreement chi2/dof mean %.2f (1 when consistent)\n",
               heads_.size(), static_cast<unsigned long long>(head_steps_),
               static_cast<unsigned long long>(merged_), static_cast<unsigned long long>(disagreed_),
               heads_chi2_.mean());
  for (const HeadSeries& h : heads_) {
    std::fprintf(out, "  head %-10s solved %5.1f %%, own fixes vs GROUND_TRUTH in its frame "
                 "[arcsec]: cross-boresight RMS %.2f, roll RMS %.2f, total RMS %.2f; %ld "
                 "misidentified\n",
                 h.label.c_str(), h.frames ? 100.0 * double(h.solved) / double(h.frames) : 0.0,
                 h.cross.rms(), h.roll.rms(), h.total.rms(), h.misidentified);
  }
  if (!joint_total_.empty()) {
    std::fprintf(out, "  joint fixes vs GROUND_TRUTH (body frame, roll about body z) [arcsec]: "
                 "cross-boresight RMS %.2f, roll RMS %.2f, total RMS %.2f (%llu frames)\n",
                 joint_cross_.rms(), joint_roll_.rms(), joint_total_.rms(),
                 static_cast<unsigned long long>(joint_total_.n()));
  }
}

void RunSummary::addRate(const NavStep& s) {
  if (!s.has_true_rate) return;
  if (s.has_fix_rate) rate_fix_err_.add((s.fix_rate - s.rate_true).norm() * kDegPerRad);
  if (!s.initialized) return;
  gyroless_ = gyroless_ || s.gyroless;
  const Vec3 e = s.rate_error * kDegPerRad;
  rate_x_.add(std::abs(e.x()));
  rate_y_.add(std::abs(e.y()));
  rate_z_.add(std::abs(e.z()));
  rate_total_.add(e.norm());
  if (s.gyroless) rate_nees_.add(s.rate_nees);
}

void RunSummary::printRates(std::FILE* out) const {
  if (rate_total_.empty() && rate_fix_err_.empty()) return;
  std::fprintf(out, "body rate vs GROUND_TRUTH (central differences of the true attitudes) "
               "[deg/s]:\n");
  if (!rate_total_.empty()) {
    std::fprintf(out, "  filter rate (%s) error RMS x %.5f y %.5f z %.5f total %.5f, max %.5f "
                 "(%llu steps)\n",
                 gyroless_ ? "gyroless state" : "gyro - bias", rate_x_.rms(), rate_y_.rms(),
                 rate_z_.rms(), rate_total_.rms(), rate_total_.h.max(),
                 static_cast<unsigned long long>(rate_total_.n()));
  }
  if (!rate_nees_.empty()) {
    std::fprintf(out, "  filter rate NEES: mean %.3f (3 dof), %.3f below the chi2(3) 95 %% "
                 "point\n", rate_nees_.mean(),
                 double(rate_nees_.below_q95) / double(rate_nees_.n()));
  }
  if (!rate_fix_err_.empty()) {
    std::fprintf(out, "  tracker frame-to-frame rate error RMS %.5f (%llu frames; the mean over "
                 "the frame interval)\n", rate_fix_err_.rms(),
                 static_cast<unsigned long long>(rate_fix_err_.n()));
  }
}

}  // namespace st

#include "app/live/integrity_summary.hpp"

#include <algorithm>
#include <cmath>

#include "common/conventions.hpp"

namespace st::app {

namespace {

/// Whether an error vector (body frame) is outside kSigmas x sigma + floor on some axis.
bool outsideBound(const Vec3& err_body, const Mat3& cov) {
  const double floor = arcsec2rad(IntegrityStats::kFloorArcsec);
  for (int i = 0; i < 3; ++i) {
    const double sigma = std::sqrt(std::max(0.0, cov(i, i)));
    if (!(std::abs(err_body(i)) <= IntegrityStats::kSigmas * sigma + floor)) return true;
  }
  return false;
}

bool taken(FixUse u) {
  return u == FixUse::kAccepted || u == FixUse::kInitialized || u == FixUse::kReinitialized ||
         u == FixUse::kUnfiltered;
}

}  // namespace

void IntegrityAccumulator::add(const NavStep& st) {
  IntegrityStats& s = s_;
  const auto wrong = [&s](double t) {
    if (s.first_wrong_t < 0) s.first_wrong_t = t;
  };
  // The filter's estimate is an output at every step, a truth marker between frames too
  // (a camera outage coasted on the gyro).
  if (st.initialized) {
    if (last_estimate_ >= 0 && st.t - last_estimate_ > s.longest_no_estimate_s) {
      s.longest_no_estimate_s = st.t - last_estimate_;
      s.no_estimate_from_s = last_estimate_;
      s.no_estimate_to_s = st.t;
    }
    last_estimate_ = st.t;
  }
  if (st.has_truth && st.initialized) {
    ++s.filter_steps;
    if (outsideBound(st.error.rotvec_body, st.P_att)) {
      ++s.wrong_filter_steps;
      wrong(st.t);
    }
  }
  if (!st.has_frame) return;
  if (st.fix && taken(st.use)) {
    if (last_used_ >= 0 && st.t - last_used_ > s.longest_outage_s) {
      s.longest_outage_s = st.t - last_used_;
      s.outage_from_s = last_used_;
      s.outage_to_s = st.t;
    }
    last_used_ = st.t;
  }
  if (!st.has_truth || !st.fix) return;
  ++s.fixes;
  const bool bad = outsideBound(st.fix_error.rotvec_body, st.cov_fix);
  if (taken(st.use)) {
    ++s.used_fixes;
    if (bad) {
      ++s.wrong_used_fixes;
      wrong(st.t);
    }
  } else if (bad) {
    ++s.wrong_refused_fixes;
  }
}

void printIntegritySummary(const IntegrityStats& s, std::FILE* out) {
  if (s.fixes == 0 && s.filter_steps == 0) return;
  std::fprintf(out,
               "integrity (vs GROUND_TRUTH, wrong = beyond %.0f sigma + %.0f\" on an axis): "
               "%d wrong valid outputs (wrong: %d of %d fixes used, %d of %d filter steps); "
               "%d wrong fixes refused\n",
               IntegrityStats::kSigmas, IntegrityStats::kFloorArcsec,
               s.wrong_used_fixes + s.wrong_filter_steps, s.wrong_used_fixes, s.used_fixes,
               s.wrong_filter_steps, s.filter_steps, s.wrong_refused_fixes);
  std::fprintf(out, "integrity: longest time without a used fix %.2f s (t = %.2f to %.2f s)\n",
               s.longest_outage_s, s.outage_from_s, s.outage_to_s);
  std::fprintf(out,
               "integrity: longest time without a filter estimate %.2f s (t = %.2f to %.2f s)\n",
               s.longest_no_estimate_s, s.no_estimate_from_s, s.no_estimate_to_s);
  if (s.first_wrong_t >= 0)
    std::fprintf(out, "integrity: first wrong valid output at t = %.2f s\n", s.first_wrong_t);
}

}  // namespace st::app

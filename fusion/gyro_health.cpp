#include "fusion/gyro_health.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

namespace st {

namespace {

constexpr double kMedianAbsNormal = 0.6745;  // median |N(0, 1)|
const char* const kAxis[] = {"x", "y", "z"};

double median(std::vector<double> v) {
  const std::size_t n = v.size() / 2;
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(n), v.end());
  if (v.size() % 2 == 1) return v[n];
  const double hi = v[n];
  const double lo = *std::max_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(n));
  return 0.5 * (lo + hi);
}

template <class T>
void pushCapped(std::deque<T>& d, T v, std::size_t cap) {
  d.push_back(v);
  while (d.size() > cap) d.pop_front();
}

}  // namespace

// The messages name the [navigator] keys (navigation/tracker_ini.cpp) that set the fields.
bool GyroHealthOptions::isValid(std::string* why) const {
  auto bad = [&](const char* msg) {
    if (why) *why = msg;
    return false;
  };
  if (!(max_angular_accel_rad_s2 >= 0) || !std::isfinite(max_angular_accel_rad_s2))
    return bad("'gyro_max_accel_deg_s2': must be >= 0");
  if (!(spike_sigmas > 0)) return bad("'gyro_spike_sigmas': must be > 0");
  if (median_of < 1) return bad("'gyro_spike_median_of': must be >= 1");
  if (step_after < 2) return bad("'gyro_step_after': must be >= 2");
  if (window < 4) return bad("'gyro_health_window': must be >= 4");
  if (!(noise_factor > 1)) return bad("'gyro_noise_factor': must be > 1");
  if (noisy_flags < 1) return bad("'gyro_noisy_flags': must be >= 1");
  return true;
}

void GyroHealth::reset() {
  ax_ = {};
  healthy_ = true;
  clean_run_ = 0;
}

GyroSampleCheck GyroHealth::check(const Vec3& rate, double dt, double sigma_s) {
  GyroSampleCheck out;
  out.rate = rate;
  out.healthy = healthy_;
  if (!o_.enabled || !(dt > 0)) return out;
  const bool noise_known = sigma_s > 0;
  const auto m = static_cast<std::size_t>(o_.median_of);
  const auto w = static_cast<std::size_t>(o_.window);
  const double thr = o_.spike_sigmas * sigma_s * std::sqrt(1.0 + kPi / (2.0 * o_.median_of)) +
                     o_.max_angular_accel_rad_s2 * dt * (o_.median_of + 1) / 2.0;
  bool flagged_any = false;
  int repeats[3] = {0, 0, 0};
  for (int i = 0; i < 3; ++i) {
    Axis& a = ax_[i];
    const double x = rate(i);
    const bool rep = !a.raw.empty() && x == a.raw.back();
    pushCapped(a.raw, x, w + 2);
    pushCapped(a.repeat, rep, w);
    bool flagged = false;
    if (noise_known && a.accepted.size() >= m) {
      const double med = median({a.accepted.begin(), a.accepted.end()});
      if (std::abs(x - med) > thr) {
        a.pending.push_back(x);
        a.pending_error += (x - med) * dt;
        const auto [lo, hi] = std::minmax_element(a.pending.begin(), a.pending.end());
        if (static_cast<int>(a.pending.size()) >= o_.step_after && *hi - *lo <= thr) {
          // A real rate step: the new level holds. The samples replaced before were right.
          out.step_error(i) = a.pending_error - (x - med) * dt;
          a.accepted.assign(a.pending.begin(), a.pending.end());
          for (std::size_t k = 1; k < a.pending.size() && k <= a.flag.size(); ++k)
            a.flag[a.flag.size() - k] = false;
          a.pending.clear();
          a.pending_error = 0;
        } else {
          flagged = true;
          out.rate(i) = med;
          if (static_cast<int>(a.pending.size()) >= o_.step_after) {
            // Disagreeing flags in a row: noise, not a step; keep the latest ones only.
            a.pending.pop_front();
            a.pending_error = 0;
            for (double p : a.pending) a.pending_error += (p - med) * dt;
          }
        }
      } else {
        a.pending.clear();
        a.pending_error = 0;
      }
    }
    if (!flagged) pushCapped(a.accepted, x, m);
    pushCapped(a.flag, flagged, w);
    flagged_any = flagged_any || flagged;
    repeats[i] = static_cast<int>(std::count(a.repeat.begin(), a.repeat.end(), true));
  }
  if (flagged_any) {
    out.spike = true;
    ++spikes_;
  }
  // Stuck and noisy axes.
  std::string found;
  if (noise_known) {
    for (int i = 0; i < 3 && found.empty(); ++i) {
      const Axis& a = ax_[i];
      if (a.repeat.size() < w) continue;
      bool another_moves = false;
      for (int j = 0; j < 3; ++j) another_moves = another_moves || (j != i && 4 * repeats[j] < o_.window);
      char b[160];
      if (2 * repeats[i] >= o_.window && another_moves) {
        std::snprintf(b, sizeof b, "axis %s stuck (%d of the last %d readings repeat exactly)",
                      kAxis[i], repeats[i], o_.window);
        found = b;
        break;
      }
      const int flags = static_cast<int>(std::count(a.flag.begin(), a.flag.end(), true));
      if (flags >= o_.noisy_flags) {
        std::snprintf(b, sizeof b, "axis %s noisy (%d of the last %d samples are spikes)",
                      kAxis[i], flags, o_.window);
        found = b;
        break;
      }
      if (a.raw.size() >= w + 2) {
        std::vector<double> d2;
        d2.reserve(w);
        for (std::size_t k = 2; k < a.raw.size(); ++k)
          d2.push_back(std::abs(a.raw[k] - 2 * a.raw[k - 1] + a.raw[k - 2]));
        const double healthy_med = kMedianAbsNormal * std::sqrt(6.0) * sigma_s;
        const double med = median(d2);
        if (med > o_.noise_factor * healthy_med) {
          std::snprintf(b, sizeof b,
                        "axis %s noisy (median |second difference| %.3g deg/s, %.1fx the "
                        "datasheet's %.3g deg/s)",
                        kAxis[i], med * 180 / kPi, med / healthy_med, healthy_med * 180 / kPi);
          found = b;
        }
      }
    }
  }
  const bool clean = found.empty() && !flagged_any;
  clean_run_ = clean ? clean_run_ + 1 : 0;
  if (healthy_ && !found.empty()) {
    healthy_ = false;
    out.changed = true;
    out.why = found;
  } else if (!healthy_ && clean_run_ >= o_.window) {
    healthy_ = true;
    out.changed = true;
    out.why = "healthy again (" + std::to_string(o_.window) + " samples in a row pass every check)";
  }
  out.healthy = healthy_;
  return out;
}

}  // namespace st

// What the live tests read back from `startracker live`: its summary lines and the CSV of
// its filter steps, and the chi-square fraction test on the filter's NEES.
#pragma once
#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "fusion/consistency.hpp"
#include "tests/support/csv_file.hpp"

namespace st::test {

struct LiveSummary {
  std::string rawlog;
  std::size_t total = 0;
  std::map<std::string, std::size_t> per_label;
  int frames = -1, solved = -1, tracking = -1;
};

inline LiveSummary parseLiveSummary(const std::string& out) {
  LiveSummary s;
  std::smatch m;
  if (std::regex_search(out, m, std::regex(R"(rawlog: (.+), (\d+) observations)"))) {
    s.rawlog = m[1];
    s.total = std::stoul(m[2]);
  }
  std::istringstream in(out);
  std::string line;
  const std::regex label(R"(^  (\S+)\s+(\d+)$)");
  while (std::getline(in, line)) {
    if (std::regex_match(line, m, label)) s.per_label[m[1]] = std::stoul(m[2]);
  }
  if (std::regex_search(out, m,
                        std::regex(R"(star tracker: (\d+) frames, (\d+) solved .*, (\d+) tracking)"))) {
    s.frames = std::stoi(m[1]);
    s.solved = std::stoi(m[2]);
    s.tracking = std::stoi(m[3]);
  }
  return s;
}

inline double fractionBelow(const std::vector<double>& nees, double p) {
  const double q = chiSquareQuantile(p, 3.0);
  return double(std::count_if(nees.begin(), nees.end(), [&](double v) { return v <= q; })) /
         double(nees.size());
}

/// Replay's per-frame NEES test (its 3000-frame test's bound): the fraction of the filter's
/// NEES below the chi-square(3) quantile p must be p, within 3 binomial sigma of N/10
/// effective samples (successive filter steps are correlated). The teeth: the same errors
/// against a covariance 4x too small must fail it. Returns a one-line report.
inline std::string neesFractionsInBand(const std::vector<double>& nees, bool* ok) {
  const double n_eff = double(nees.size()) / 10.0;
  const double tol50 = 3.0 * std::sqrt(0.25 / n_eff), tol95 = 3.0 * std::sqrt(0.0475 / n_eff);
  const double f50 = fractionBelow(nees, 0.5), f95 = fractionBelow(nees, 0.95);
  std::vector<double> over(nees);
  for (double& v : over) v *= 4.0;
  const bool teeth = std::abs(fractionBelow(over, 0.5) - 0.5) > tol50;
  *ok = std::abs(f50 - 0.5) <= tol50 && std::abs(f95 - 0.95) <= tol95 && teeth;
  char b[240];
  std::snprintf(b, sizeof b,
                "filter NEES: %.3f below the chi2(3) median (+-%.3f), %.3f below its 95 %% point "
                "(+-%.3f), %zu frames; 4x-optimistic covariance %s",
                f50, tol50, f95, tol95, nees.size(), teeth ? "fails (teeth)" : "PASSES (no teeth)");
  return b;
}

}  // namespace st::test

// Double-star merge (seed 004 eqs. 6.1 and 6.2) with a z-sorted sweep and union-find.
#include "catalog/star_selection.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "common/conventions.hpp"

namespace st {

double combinedMagnitude(double m1, double m2) {
  // seed 004 eq. 6.1: M = M2 - 2.5 log10(1 + 10^((M2 - M1) / 2.5))
  return m2 - 2.5 * std::log10(1.0 + std::pow(10.0, (m2 - m1) / 2.5));
}

std::vector<SelectedStar> mergeDoubleStars(const std::vector<SelectedStar>& in, double sep,
                                           std::size_t* groups, std::size_t* absorbed) {
  if (groups) *groups = 0;
  if (absorbed) *absorbed = 0;
  if (!(sep > 0) || in.size() < 2) return in;
  const std::size_t n = in.size();
  std::vector<uint32_t> by_z(n);
  std::iota(by_z.begin(), by_z.end(), 0u);
  std::sort(by_z.begin(), by_z.end(), [&](uint32_t a, uint32_t b) { return in[a].u.z() < in[b].u.z(); });
  std::vector<uint32_t> parent(n);
  std::iota(parent.begin(), parent.end(), 0u);
  auto find = [&](uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  const double cos_sep = std::cos(sep);
  // Two stars within `sep` differ in z by at most the chord 2 sin(sep/2) < sep.
  for (std::size_t i = 0; i < n; ++i) {
    const SelectedStar& si = in[by_z[i]];
    for (std::size_t j = i + 1; j < n && in[by_z[j]].u.z() - si.u.z() <= sep; ++j)
      if (si.u.dot(in[by_z[j]].u) >= cos_sep) parent[find(by_z[i])] = find(by_z[j]);
  }
  // Accumulate intensity I = 10^(-0.4 m) and the intensity-weighted direction per group.
  std::vector<double> flux(n, 0.0);
  std::vector<Vec3> dir(n, Vec3::Zero());
  std::vector<uint32_t> brightest(n, UINT32_MAX), members(n, 0);
  for (uint32_t k = 0; k < n; ++k) {
    const uint32_t r = find(k);
    const double f = relativeFlux(in[k].mag);
    flux[r] += f;
    dir[r] += f * in[k].u;  // eq. 6.2: weights 10^((M - M_i)/2.5) = I_i / I_total
    ++members[r];
    if (brightest[r] == UINT32_MAX || in[k].mag < in[brightest[r]].mag) brightest[r] = k;
  }
  std::vector<SelectedStar> out;
  out.reserve(n);
  for (uint32_t r = 0; r < n; ++r) {
    if (members[r] == 0) continue;
    if (members[r] == 1) {
      out.push_back(in[r]);
      continue;
    }
    if (groups) ++*groups;
    if (absorbed) *absorbed += members[r] - 1;
    out.push_back({in[brightest[r]].id, dir[r].normalized(), -2.5 * std::log10(flux[r])});
  }
  return out;
}

}  // namespace st

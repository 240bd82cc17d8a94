/// @file cone_index.hpp
/// Directions within a cone of the sky, found without a scan (seed 002 spherical-polygon
/// search): for each axis c the directions sorted by their c-coordinate with a k-vector on it
/// (seed 000 eqs. 11-14); a query takes the thinnest of the three coordinate slabs that must
/// hold every match and tests only the directions in it.
#pragma once
#include <cstddef>
#include <cstdint>
#include <vector>

#include "catalog/kvector.hpp"
#include "common/attitude.hpp"

namespace st {

class ConeIndex {
 public:
  /// Indexes unit vectors `u` (kept by index: a query returns positions in `u`).
  void build(const std::vector<Vec3>& u);
  /// Indices of the directions within `radius` [rad] of `axis` (unit), ascending. `out` is
  /// cleared first.
  void query(const Vec3& axis, double radius, std::vector<uint32_t>& out) const;
  std::size_t size() const { return n_; }

 private:
  // For each axis c: indices sorted by u[c], the sorted coordinates, and the k-vector on
  // them; plus the vectors in that order for a tight candidate loop.
  struct AxisIndex {
    std::vector<uint32_t> order;
    std::vector<Vec3> u;
    std::vector<double> coord;
    KVector kv;
  };
  AxisIndex axis_[3];
  std::size_t n_ = 0;
};

}  // namespace st

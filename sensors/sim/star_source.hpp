/// @file star_source.hpp
/// Where the simulator's stars come from: the star database (the normal case) or a plain
/// list (tests, synthetic fields). Both answer "which stars lie within `radius` of `axis`".
#pragma once
#include <cstdint>
#include <vector>

#include "common/attitude.hpp"

namespace st {

class StarDatabase;

struct SkyStar {
  uint32_t id;  ///< catalog id (HIP / HR); 0 for clutter that is not a catalog star
  Vec3 u_i;     ///< unit vector, inertial, at the observation epoch
  double mag;   ///< V magnitude
};

class StarSource {
 public:
  virtual ~StarSource() = default;
  /// Appends to `out` (cleared first) the stars within `radius` [rad] of the unit vector `axis_i`.
  virtual void query(const Vec3& axis_i, double radius, std::vector<SkyStar>& out) const = 0;
};

/// A fixed list, searched by brute force.
class ListStarSource : public StarSource {
 public:
  explicit ListStarSource(std::vector<SkyStar> stars) : stars_(std::move(stars)) {}
  void query(const Vec3& axis_i, double radius, std::vector<SkyStar>& out) const override;
  const std::vector<SkyStar>& stars() const { return stars_; }

 private:
  std::vector<SkyStar> stars_;
};

/// The stars of a StarDatabase (which must outlive this object), via its cone index.
class DatabaseStarSource : public StarSource {
 public:
  explicit DatabaseStarSource(const StarDatabase& db) : db_(db) {}
  void query(const Vec3& axis_i, double radius, std::vector<SkyStar>& out) const override;

 private:
  const StarDatabase& db_;
  mutable std::vector<uint32_t> idx_;  // scratch (not thread-safe, like the renderer)
};

}  // namespace st

#include "sensors/sim/star_source.hpp"

#include <cmath>

#include "catalog/star_database.hpp"

namespace st {

void ListStarSource::query(const Vec3& axis_i, double radius, std::vector<SkyStar>& out) const {
  out.clear();
  const double c = std::cos(radius);
  for (const SkyStar& s : stars_)
    if (s.u_i.dot(axis_i) >= c) out.push_back(s);
}

void DatabaseStarSource::query(const Vec3& axis_i, double radius,
                               std::vector<SkyStar>& out) const {
  out.clear();
  db_.coneQuery(axis_i, radius, idx_);
  const auto& stars = db_.stars();
  out.reserve(idx_.size());
  for (uint32_t i : idx_) out.push_back({stars[i].id, stars[i].u_i, static_cast<double>(stars[i].mag)});
}

}  // namespace st

/// @file triangle_features.hpp
/// Area and polar moment of the triangle spanned by three unit vectors (seed 001):
/// planar (chords, eq. 2-7) and spherical (arcs, eq. 8-12). Invariant under rotation, so
/// the same numbers come from camera-frame observations and inertial catalog vectors.
#pragma once
#include "common/attitude.hpp"

namespace st {

struct TriangleFeature {
  double area = 0;          ///< planar [rad^2-ish chord units] or spherical [sr]
  double polar_moment = 0;  ///< planar [units^4] or spherical [sr rad^2]
};

TriangleFeature planarTriangle(const Vec3& b1, const Vec3& b2, const Vec3& b3);
/// `depth` levels of 4-way subdivision for the polar moment sum (eq. 12).
TriangleFeature sphericalTriangle(const Vec3& b1, const Vec3& b2, const Vec3& b3,
                                  int depth = 2);

}  // namespace st

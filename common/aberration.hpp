/// @file aberration.hpp
/// Stellar aberration: the direction in which an observer moving at `velocity_km_s` sees light
/// arriving from `u`. One formula for the catalog's annual aberration (the Earth's orbit,
/// catalog/epoch_correction.hpp), the observer's own orbit (sensors/tracking/
/// observer_aberration.hpp, fusion's star-vector updates) and the simulator.
#pragma once
#include "common/attitude.hpp"

namespace st {

/// Special-relativistic form: u' = (u / gamma + (1 + u.beta / (1 + 1/gamma)) beta) / (1 + u.beta),
/// beta = v / c. Velocities compose to O(beta^2) = 1e-8 rad by applying them in turn.
Vec3 applyAberration(const Vec3& u, const Vec3& velocity_km_s);

}  // namespace st

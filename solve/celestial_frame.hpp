/// @file celestial_frame.hpp
/// Which celestial frame `solve`'s attitude is in, and how a solution moves between frames.
///  - apparent (default): star directions as the observer sees them, with the Earth's annual
///    aberration (up to 20.5") and, with --observer-velocity-km-s, the observer's own
///    velocity w.r.t. the Earth's centre (a spacecraft, up to ~8 km/s = 5.5") added to it;
///  - astrometric (--no-aberration): catalog (ICRS) directions at the epoch, without
///    aberration: the frame of astrometry.net's solutions and of a FITS WCS.
/// A star database holds its stars in one of these (its aberration flag, Earth's velocity at
/// its epoch). When the request differs, every matched star's catalog vector is moved from
/// the database's frame to the requested one and Wahba is solved again between the two sets:
/// aberration over a field is a rotation plus a field distortion below 1e-4 of the field
/// (v/c), so the residuals do not change and the rotation is what the frame change does to
/// the attitude.
#pragma once
#include <string>

#include "catalog/star_database.hpp"
#include "common/attitude.hpp"
#include "sensors/identify/identifier.hpp"

namespace st::solve {

struct SolveOptions;

struct CelestialFrame {
  bool annual = true;              ///< the Earth's annual aberration
  Vec3 observer_km_s = Vec3::Zero();  ///< added velocity (GCRS/ICRS axes)
  bool apparent() const { return annual || observer_km_s.squaredNorm() > 0; }
  const char* name() const { return apparent() ? "apparent" : "astrometric"; }
  /// The observer's total velocity [km/s] the frame's aberration is for at `epoch_jyear`.
  Vec3 velocity(double epoch_jyear) const;
  /// One line for the text report, e.g. "apparent: annual aberration at 2019.57".
  std::string describe(double epoch_jyear) const;
};

/// The frame asked for; InputError for --no-aberration with a velocity, or a velocity that is
/// not finite or not below the speed of light.
CelestialFrame requestedFrame(const SolveOptions& o);

/// The frame a database's stars are in.
CelestialFrame databaseFrame(const DatabaseParams& p);

/// Moves a solution whose matched stars are db's from frame `from` at `from_jyear` to frame
/// `to` at `to_jyear`; a no-op when both give the same velocity.
void changeFrame(IdentifyResult& res, const StarDatabase& db, const CelestialFrame& from,
                 double from_jyear, const CelestialFrame& to, double to_jyear);

}  // namespace st::solve

#include "solve/solve_epoch.hpp"

#include <cmath>
#include <ctime>
#include <cstdio>

#include "catalog/epoch_correction.hpp"
#include "common/conventions.hpp"
#include "common/errors.hpp"

namespace st::solve {

SolveEpoch chooseEpoch(double cli_epoch, const std::optional<double>& frame_epoch,
                       const std::string& frame_source, const StarDatabase* db_file) {
  if (cli_epoch > 0) return {cli_epoch, "--epoch"};
  if (frame_epoch) return {*frame_epoch, frame_source};
  if (db_file) return {db_file->params().epoch_jyear, "database"};
  return {julianYearFromUnixSeconds(static_cast<double>(std::time(nullptr))), "today"};
}

namespace {
constexpr double kSpeedOfLightKmS = 299792.458;

struct ShiftParts {
  double proper_motion = 0, aberration = 0, parallax = 0;  // [arcsec]
  double total() const { return proper_motion + aberration + parallax; }
};

ShiftParts epochShift(const DatabaseParams& p, double epoch_jyear) {
  ShiftParts s;
  s.proper_motion = kMaxProperMotionArcsecPerYear * std::abs(epoch_jyear - p.epoch_jyear);
  const EarthState a = earthBarycentricState(p.epoch_jyear), b = earthBarycentricState(epoch_jyear);
  // To first order the aberration shift is |u x (beta x u)| <= |beta|: its change is bounded
  // by the change of beta.
  if (p.aberration)
    s.aberration = rad2arcsec((b.velocity_km_s - a.velocity_km_s).norm() / kSpeedOfLightKmS);
  if (p.parallax) s.parallax = kMaxParallaxArcsec * (b.position_au - a.position_au).norm();
  return s;
}
}  // namespace

double epochShiftBoundArcsec(const DatabaseParams& p, double epoch_jyear) {
  return epochShift(p, epoch_jyear).total();
}

void requireDatabaseEpoch(const StarDatabase& db, const std::string& path, const SolveEpoch& e) {
  const DatabaseParams& p = db.params();
  const ShiftParts s = epochShift(p, e.jyear);
  if (s.total() <= kEpochToleranceArcsec) return;
  char b[900];
  std::snprintf(
      b, sizeof b,
      "the observation epoch %.4f (from %s) differs from the epoch %.4f of the star database "
      "%s: stars move up to %.1f arcsec between them (proper motion up to %.1f arcsec/yr over "
      "%.3f yr: %.1f, annual aberration: %.1f, parallax: %.2f arcsec), more than the %.0f "
      "arcsec tolerance, and a database holds no proper motions to move them. Rebuild it for "
      "this epoch: startracker catalog build --epoch %.4f -o NEW.db with the options it was "
      "built with (pairs up to %.2f deg, V <= %.2f), or leave out --database to build one in "
      "memory",
      e.jyear, e.source.c_str(), p.epoch_jyear, path.c_str(), s.total(),
      kMaxProperMotionArcsecPerYear, std::abs(e.jyear - p.epoch_jyear), s.proper_motion,
      s.aberration, s.parallax, kEpochToleranceArcsec, e.jyear, rad2deg(p.max_pair_angle),
      p.mag_limit);
  throw InputError(b);
}

}  // namespace st::solve

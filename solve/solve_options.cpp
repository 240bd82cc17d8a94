// The plate solver's options and their checks (the command's flags are app/cmd_solve.cpp).
#include "solve/solve_options.hpp"

#include <cstdio>
#include <memory>

#include "common/conventions.hpp"
#include "common/errors.hpp"
#include "sensors/attitude/wahba.hpp"

namespace st::solve {

ParityChoice SolveOptions::parityChoice() const {
  if (parity == "normal") return ParityChoice::Normal;
  if (parity == "flipped") return ParityChoice::Flipped;
  return ParityChoice::Both;
}

std::optional<PositionHint> SolveOptions::positionHint() const {
  const int given = int(!std::isnan(ra_deg)) + int(!std::isnan(dec_deg)) + int(!std::isnan(radius_deg));
  if (given == 0) return std::nullopt;
  // The names the caller's user knows: the command's flags, or the library's fields.
  const bool cli = !option_prefix.empty();
  const std::string ra = cli ? "--ra" : "ra_deg", dec = cli ? "--dec" : "dec_deg",
                    radius = cli ? "--radius" : "radius_deg";
  if (given != 3)
    throw InputError(ra + ", " + dec + " and " + radius +
                     " go together: the hint is a circle on the sky");
  if (!(ra_deg >= 0 && ra_deg <= 360))
    throw InputError(ra + " " + std::to_string(ra_deg) + ": must be in [0, 360] deg");
  if (!(dec_deg >= -90 && dec_deg <= 90))
    throw InputError(dec + " " + std::to_string(dec_deg) + ": must be in [-90, 90] deg");
  if (!(radius_deg > 0 && radius_deg <= 180))
    throw InputError(radius + " " + std::to_string(radius_deg) + ": must be in (0, 180] deg");
  return PositionHint{deg2rad(ra_deg), deg2rad(dec_deg), deg2rad(radius_deg)};
}

namespace {
void checkFov(const std::string& what, const CameraModel& widest, const CameraModel& finest) {
  char b[400];
  const double diag = rad2deg(2 * widest.halfDiagonalFov());
  if (!(diag <= kMaxSolveDiagonalDeg)) {
    std::snprintf(b, sizeof b,
                  "%s: a %dx%d image with a %.1f deg horizontal field of view has a %.1f deg "
                  "diagonal; solve takes fields up to a %.0f deg diagonal (a pinhole lens model; "
                  "fisheye and all-sky images are not supported)",
                  what.c_str(), widest.width(), widest.height(), rad2deg(widest.horizontalFov()),
                  diag, kMaxSolveDiagonalDeg);
    throw InputError(b);
  }
  const double scale = rad2deg(finest.pixelScale());
  if (!(scale <= kMaxSolvePixelScaleDeg)) {
    std::snprintf(b, sizeof b,
                  "%s: a %dx%d image with a %.1f deg horizontal field of view has %.2f deg "
                  "pixels; solve takes pixels up to %.2f deg (a larger image, or a narrower field)",
                  what.c_str(), finest.width(), finest.height(), rad2deg(finest.horizontalFov()),
                  scale, kMaxSolvePixelScaleDeg);
    throw InputError(b);
  }
}

std::string num(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%g", v);
  return b;
}
}  // namespace

void requireSolvableFov(const SolveOptions& o, int w, int h) {
  if (o.camera.given()) {
    const CameraModel cam = o.camera.resolve(w, h);
    checkFov(o.camera.camera_file.empty() ? "--fov-deg " + num(o.camera.fov_deg)
                                          : o.camera.camera_file,
             cam, cam);
    return;
  }
  const auto& r = o.fov_range_deg;
  if (r.size() != 2 || !(r[0] > 0) || !(r[1] >= r[0])) return;  // cameraSearch says why
  const double aspect = o.camera.pixelAspect(o.option_prefix);
  checkFov("--fov-range " + num(r[0]) + " " + num(r[1]),
           CameraModel::fromFov(w, h, deg2rad(r[1]), aspect),
           CameraModel::fromFov(w, h, deg2rad(r[0]), aspect));
}

}  // namespace st::solve

/// @file wcs_reference.hpp
/// Test helper: an astrometry.net solution (FITS WCS header, TAN with SIP distortion, as the
/// .wcs files beside the real frames) as an outside reference: the sky direction of a pixel
/// and the pixel of a sky direction. Independent of the project's camera model on purpose.
#pragma once
#include <map>
#include <string>

namespace st::test {

class WcsReference {
 public:
  /// Reads the header; `rows_doubled`: the solution was made on the frame with every row
  /// doubled (the Swarm frames'), so y_here = (y_wcs + 0.5) / 2 - 0.5. Throws on a bad file.
  WcsReference(const std::string& path, bool rows_doubled);
  /// 0-based pixel of this image -> RA, Dec [rad].
  void pixelToSky(double x, double y, double& ra, double& dec) const;
  /// RA, Dec [rad] -> 0-based pixel (false behind the tangent plane).
  bool skyToPixel(double ra, double dec, double& x, double& y) const;

 private:
  double key(const std::string& k, double fallback = 0) const;
  double sip(const std::string& prefix, double u, double v) const;
  std::map<std::string, double> h_;
  bool rows_doubled_;
};

/// Great-circle angle [arcsec] between two directions given in radians.
double separationArcsec(double ra1, double dec1, double ra2, double dec2);

}  // namespace st::test

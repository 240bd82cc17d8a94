/// @file photometry.hpp
/// Magnitudes from the measured flux of identified stars: instrument magnitudes, a zero
/// point, a colour term and an off-axis fall-off fitted on the stars of a solved frame, and
/// the magnitude consistency test that lost-in-space uses when only two or three stars are
/// seen (identifier.hpp, IdentifyOptions::magnitude_sigma).
///
/// Model (seed 003 "Correction to CCD-Sensitivity"; seed 004 sec. 5.3 instrument magnitudes):
///     V = m_inst + ZP + c (B-V) + n * 2.5 log10(cos theta),   m_inst = -2.5 log10(F / t)
/// F the background-subtracted flux [ADU], t the exposure [s], theta the angle from the
/// optical axis. c (B-V) is the first-order colour correction of seed 003's CCD-brightness
/// ratio sum(M S T) / sum(M V) for a detector band other than V; cos^n theta the off-axis
/// fall-off seed 003 describes without a law (n = 4 for the natural cos^4 vignetting of a
/// thin lens). The zero point is for B-V = 0.
///
/// Fit: least squares with iterative clipping, started from the median with a cut at
/// `clip_sigma` robust sigmas (1.4826 x the median absolute deviation), then at `clip_sigma`
/// standard deviations of the kept residuals (clipped stars may come back) until stable.
/// The colour term is fitted only with enough stars of known B-V spanning a colour range; the exponent n only when its standard
/// error is below max_exponent_se (a narrow field cannot tell cos^4 from cos^0: 2.5 log10
/// cos 7 deg = -0.008 mag), else it is fixed at `off_axis_exponent`.
#pragma once
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "catalog/star_database.hpp"
#include "sensors/detect/centroid.hpp"
#include "sensors/identify/star_match.hpp"
#include "sensors/identify/star_observation.hpp"

namespace st {

/// -2.5 log10(flux / exposure): NaN for a flux <= 0 or an exposure <= 0.
double instrumentMagnitude(double flux_adu, double exposure_s);
/// The off-axis term's regressor 2.5 log10(cos theta) [mag] (<= 0): V gains n times it.
double offAxisRegressor(double off_axis_rad);

struct PhotometryStar {
  double m_inst = 0;       ///< instrument magnitude (instrumentMagnitude)
  double off_axis = 0;     ///< [rad] angle from the optical axis
  double catalog_v = 0;    ///< V of the identified catalog star
  double bv = 0;           ///< B-V, NaN when unknown
  bool usable = true;      ///< false: shown, not fitted (saturated, cut by the edge)
};

struct PhotometryOptions {
  double clip_sigma = 3.0;          ///< clip residuals beyond this many robust sigmas
  int max_iterations = 10;
  bool fit_colour = true;
  int min_colour_stars = 8;         ///< stars of known B-V needed to fit c
  double min_colour_range = 0.3;    ///< [mag] spread (max - min) of their B-V needed
  bool fit_off_axis = true;
  double off_axis_exponent = 4.0;   ///< n when not fitted: cos^4 (camera's own when known)
  double max_exponent_se = 1.0;     ///< fit n only when its standard error is below this
  int min_stars = 3;                ///< fewer usable stars: no fit

  /// True when all values are usable; otherwise false with `why` naming the field.
  bool isValid(std::string* why = nullptr) const;
};

struct PhotometryFit {
  bool ok = false;
  std::string reason;                 ///< why not ok
  double zero_point = 0;              ///< [mag] ZP at B-V = 0
  double zero_point_se = 0;           ///< [mag] its standard error
  double colour_term = 0;             ///< c
  double colour_term_se = 0;
  bool colour_fitted = false;
  double off_axis_exponent = 0;       ///< n (fitted or fixed)
  double off_axis_se = 0;             ///< 0 when fixed
  bool off_axis_fitted = false;
  double scatter = 0;                 ///< [mag] standard deviation of the kept residuals
                                      ///< (sum r^2 / (kept - parameters))
  double robust_sigma = 0;            ///< [mag] 1.4826 x MAD of the kept residuals
  double rms = 0;                     ///< [mag] RMS of the kept residuals
  int used = 0;                       ///< stars in the final fit
  int clipped = 0;                    ///< usable stars clipped
  std::vector<double> fitted;         ///< per star: V predicted from m_inst (NaN without m_inst)
  std::vector<double> residual;       ///< per star: catalog V - fitted
  std::vector<bool> kept;             ///< per star: in the final fit
};

/// Fits the model above on `stars`; !ok (with reason) when fewer than min_stars are usable.
/// Precondition: options.isValid().
PhotometryFit fitPhotometry(const std::vector<PhotometryStar>& stars,
                            const PhotometryOptions& options = {});

/// The identified stars of a solved frame as the fit sees them, in the order of `matches`:
/// m_inst from centroids[obs_index].flux and `exposure_s`, the off-axis angle from
/// obs[obs_index].v_cam, V from the database, B-V from `bv_of(catalog id)` (NaN unknown; an
/// empty function: all unknown). Saturated or edge-cut stars are not usable (flux lost).
std::vector<PhotometryStar> photometryStars(const std::vector<Centroid>& centroids,
                                            const std::vector<StarObservation>& obs,
                                            const std::vector<StarMatch>& matches,
                                            const StarDatabase& db, double exposure_s,
                                            const std::function<double(uint32_t)>& bv_of = {});

/// 1.4826 x median |x - median x| (the sigma of a normal sample); 0 for an empty input.
double robustSigma(std::vector<double> x);

}  // namespace st

#include "sensors/identify/photometry.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include <Eigen/Dense>

#include "common/check.hpp"

namespace st {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double median(std::vector<double> x) {
  if (x.empty()) return 0;
  const std::size_t h = x.size() / 2;
  std::nth_element(x.begin(), x.begin() + static_cast<long>(h), x.end());
  const double hi = x[h];
  if (x.size() % 2) return hi;
  return 0.5 * (hi + *std::max_element(x.begin(), x.begin() + static_cast<long>(h)));
}

/// One clipped least-squares fit of y = X beta on the rows, all columns given.
struct Clipped {
  bool ok = false;
  Eigen::VectorXd beta;
  Eigen::MatrixXd cov;
  std::vector<bool> kept;
  double scatter = 0, robust = 0, rms = 0;
  int used = 0;
};

Clipped fitClipped(const Eigen::MatrixXd& X, const Eigen::VectorXd& y, double clip_sigma,
                   int max_iterations) {
  const int n = static_cast<int>(y.size()), p = static_cast<int>(X.cols());
  Clipped c;
  // A clip scale never below 1 mmag: exact (noise-free) data would otherwise clip on rounding.
  const auto clipAt = [&](const std::vector<double>& r_kept) {
    return clip_sigma * std::max(1e-3, robustSigma(r_kept));
  };
  // Start: the median offset, robust against the outliers the first least squares would chase.
  const double m0 = median(std::vector<double>(y.data(), y.data() + n));
  std::vector<double> r0(n);
  for (int i = 0; i < n; ++i) r0[i] = y[i] - m0;
  const double lim0 = clipAt(r0);
  c.kept.assign(n, false);
  for (int i = 0; i < n; ++i) c.kept[i] = std::abs(r0[i]) <= lim0;
  for (int it = 0; it < max_iterations; ++it) {
    const int k = static_cast<int>(std::count(c.kept.begin(), c.kept.end(), true));
    if (k <= p) return c;
    Eigen::MatrixXd Xk(k, p);
    Eigen::VectorXd yk(k);
    for (int i = 0, j = 0; i < n; ++i)
      if (c.kept[i]) Xk.row(j) = X.row(i), yk[j++] = y[i];
    const Eigen::MatrixXd N = Xk.transpose() * Xk;
    Eigen::FullPivLU<Eigen::MatrixXd> lu(N);
    if (lu.rank() < p) return c;
    c.beta = lu.solve(Xk.transpose() * yk);
    const Eigen::VectorXd r = y - X * c.beta;
    std::vector<double> rk;
    double ss = 0;
    for (int i = 0; i < n; ++i)
      if (c.kept[i]) rk.push_back(r[i]), ss += r[i] * r[i];
    c.used = k;
    c.robust = robustSigma(rk);
    c.scatter = std::sqrt(ss / std::max(1, k - p));
    c.rms = std::sqrt(ss / k);
    c.cov = (k > p ? ss / (k - p) : 0.0) * lu.inverse();
    c.ok = true;
    // Later rounds clip at the standard deviation of the kept stars: a robust sigma of a
    // dozen residuals can be half the true one and would clip honest stars.
    const double lim = clip_sigma * std::max(1e-3, c.scatter);
    std::vector<bool> next(n);
    for (int i = 0; i < n; ++i) next[i] = std::abs(r[i]) <= lim;
    if (next == c.kept) break;
    c.kept = next;
  }
  return c;
}

}  // namespace

double instrumentMagnitude(double flux_adu, double exposure_s) {
  if (!(flux_adu > 0) || !(exposure_s > 0)) return kNaN;
  return -2.5 * std::log10(flux_adu / exposure_s);  // seed 004 sec. 5.3, Pogson's law
}

double offAxisRegressor(double off_axis_rad) {
  return 2.5 * std::log10(std::max(1e-12, std::cos(off_axis_rad)));
}

std::vector<PhotometryStar> photometryStars(const std::vector<Centroid>& centroids,
                                            const std::vector<StarObservation>& obs,
                                            const std::vector<StarMatch>& matches,
                                            const StarDatabase& db, double exposure_s,
                                            const std::function<double(uint32_t)>& bv_of) {
  std::vector<PhotometryStar> out;
  out.reserve(matches.size());
  for (const StarMatch& m : matches) {
    ST_ASSERT(m.obs_index < centroids.size() && m.obs_index < obs.size());
    const Centroid& c = centroids[m.obs_index];
    PhotometryStar s;
    s.m_inst = instrumentMagnitude(c.flux, exposure_s);
    const Vec3& v = obs[m.obs_index].v_cam;
    s.off_axis = std::atan2(v.head<2>().norm(), v.z());
    s.catalog_v = db.stars()[m.star_index].mag;
    s.bv = bv_of ? bv_of(m.catalog_id) : kNaN;
    s.usable = (c.flags & (kSaturated | kTouchesEdge)) == 0;
    out.push_back(s);
  }
  return out;
}

double robustSigma(std::vector<double> x) {
  if (x.empty()) return 0;
  const double m = median(x);
  for (double& v : x) v = std::abs(v - m);
  return 1.4826 * median(std::move(x));
}

bool PhotometryOptions::isValid(std::string* why) const {
  std::ostringstream e;
  auto bad = [&](const char* key, double v, const char* want) {
    e << "PhotometryOptions." << key << " = " << v << ": " << want;
  };
  if (!(clip_sigma >= 1.5))
    bad("clip_sigma", clip_sigma, "must be >= 1.5");
  else if (max_iterations < 1)
    bad("max_iterations", max_iterations, "must be >= 1");
  else if (min_colour_stars < 3)
    bad("min_colour_stars", min_colour_stars, "must be >= 3");
  else if (!(min_colour_range >= 0))
    bad("min_colour_range", min_colour_range, "must be >= 0");
  else if (!std::isfinite(off_axis_exponent))
    bad("off_axis_exponent", off_axis_exponent, "must be finite");
  else if (!(max_exponent_se > 0))
    bad("max_exponent_se", max_exponent_se, "must be > 0");
  else if (min_stars < 2)
    bad("min_stars", min_stars, "must be >= 2");
  const std::string msg = e.str();
  if (why) *why = msg;
  return msg.empty();
}

PhotometryFit fitPhotometry(const std::vector<PhotometryStar>& stars,
                            const PhotometryOptions& o) {
  ST_ASSERT(o.isValid());
  PhotometryFit fit;
  const std::size_t n_all = stars.size();
  fit.fitted.assign(n_all, kNaN);
  fit.residual.assign(n_all, kNaN);
  fit.kept.assign(n_all, false);
  std::vector<std::size_t> rows;
  std::vector<double> known_bv;
  for (std::size_t i = 0; i < n_all; ++i) {
    const PhotometryStar& s = stars[i];
    if (!s.usable || !std::isfinite(s.m_inst) || !std::isfinite(s.catalog_v)) continue;
    rows.push_back(i);
    if (std::isfinite(s.bv)) known_bv.push_back(s.bv);
  }
  if (static_cast<int>(rows.size()) < o.min_stars) {
    fit.reason = std::to_string(rows.size()) + " usable stars, the fit needs " +
                 std::to_string(o.min_stars);
    return fit;
  }
  // A star of unknown colour counts as the typical star (the median known B-V).
  const double bv_typ = known_bv.empty() ? 0.0 : median(known_bv);
  const auto bvOf = [&](const PhotometryStar& s) { return std::isfinite(s.bv) ? s.bv : bv_typ; };
  const bool colour =
      o.fit_colour && static_cast<int>(known_bv.size()) >= o.min_colour_stars &&
      *std::max_element(known_bv.begin(), known_bv.end()) -
              *std::min_element(known_bv.begin(), known_bv.end()) >= o.min_colour_range;

  const auto attempt = [&](bool fit_n) {
    const int n = static_cast<int>(rows.size());
    const int p = 1 + (colour ? 1 : 0) + (fit_n ? 1 : 0);
    Eigen::MatrixXd X(n, p);
    Eigen::VectorXd y(n);
    for (int k = 0; k < n; ++k) {
      const PhotometryStar& s = stars[rows[k]];
      const double xo = offAxisRegressor(s.off_axis);
      int col = 0;
      X(k, col++) = 1.0;
      if (colour) X(k, col++) = bvOf(s);  // seed 003 "Correction to CCD-Sensitivity"
      if (fit_n) X(k, col++) = xo;        // seed 003: rim stars transmitted less (cos^n)
      y[k] = s.catalog_v - s.m_inst - (fit_n ? 0.0 : o.off_axis_exponent * xo);
    }
    return fitClipped(X, y, o.clip_sigma, o.max_iterations);
  };
  Clipped c;
  bool fit_n = false;
  if (o.fit_off_axis) {
    c = attempt(true);
    fit_n = c.ok && std::sqrt(c.cov(c.cov.rows() - 1, c.cov.cols() - 1)) < o.max_exponent_se;
  }
  if (!fit_n) c = attempt(false);
  if (!c.ok) {
    fit.reason = "the clipped fit kept too few stars for its parameters";
    return fit;
  }
  fit.ok = true;
  fit.zero_point = c.beta[0];
  fit.zero_point_se = std::sqrt(c.cov(0, 0));
  int col = 1;
  if (colour) {
    fit.colour_fitted = true;
    fit.colour_term = c.beta[col];
    fit.colour_term_se = std::sqrt(c.cov(col, col));
    ++col;
  }
  fit.off_axis_fitted = fit_n;
  fit.off_axis_exponent = fit_n ? c.beta[col] : o.off_axis_exponent;
  fit.off_axis_se = fit_n ? std::sqrt(c.cov(col, col)) : 0.0;
  fit.scatter = c.scatter;
  fit.robust_sigma = c.robust;
  fit.rms = c.rms;
  fit.used = c.used;
  fit.clipped = static_cast<int>(rows.size()) - c.used;
  for (std::size_t k = 0; k < rows.size(); ++k) fit.kept[rows[k]] = c.kept[k];
  for (std::size_t i = 0; i < n_all; ++i) {
    const PhotometryStar& s = stars[i];
    if (!std::isfinite(s.m_inst)) continue;
    fit.fitted[i] = s.m_inst + fit.zero_point + fit.colour_term * bvOf(s) +
                    fit.off_axis_exponent * offAxisRegressor(s.off_axis);
    fit.residual[i] = s.catalog_v - fit.fitted[i];
  }
  return fit;
}

}  // namespace st

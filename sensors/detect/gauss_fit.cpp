// "gauss": maximum-likelihood fit of the pixel-integrated Gaussian PSF (seed 004 §4.2.2,
// eq. 4.5-4.9: the MLE solves Q_x = Q_y = 0 for that model). Parameters x, y, flux F,
// background B and PSF sigma s; Levenberg-Marquardt on the weighted residuals with the
// variance of each pixel taken from the model (Poisson shot + background + read noise), i.e.
// iteratively reweighted least squares, which is the Gaussian approximation of the ML.
// Covariance: inverse Fisher information (J^T W J)^-1 at the solution, its x-y block.
//
// Speed (this runs once per star per frame, and for every predictive window):
//  - the model is separable, f_ij = fx_i * fy_j: the pixel-integrated Gaussian is evaluated
//    once per pixel EDGE per axis (cols + rows + 2 per evaluation, pixel_gaussian.hpp, from a
//    Hermite table instead of erfc/exp), and every entry of J^T W J is a row factor times a
//    weighted column sum, so the per-pixel work is 15 multiply-adds, two pixels at a time
//    (SSE2, the x86-64 baseline; a scalar loop elsewhere);
//  - one pass over the pixels per LM trial: the trial's normal equations are built with the
//    trial's own weights (IRLS) and, in the same pass, its chi2 with the stored weights of the
//    current estimate, so that accepting or rejecting it compares like with like;
//  - the start is the background-subtracted centre of gravity, so Gauss-Newton converges in
//    a few trials; once the proposed step is below 1e-3 px (position) and 1e-2 px (sigma) it
//    is taken without another pass (the remaining error is then ~1e-6 px, quadratic
//    convergence), and the Fisher information of the last pass, 1e-3 px away, gives the
//    covariance;
//  - 5x5 Cholesky by hand (no dynamic-size paths); tables, weights and the pixel copy live in
//    per-thread buffers: no allocation per star.
#include <algorithm>
#include <cmath>
#include <vector>

#include "sensors/detect/centroider.hpp"
#include "sensors/detect/gauss_fit_internal.hpp"

namespace st {
namespace {

using namespace gauss_fit_detail;

constexpr int kMaxTrials = 20;
// Stop once a proposed step is negligible, and take it without another pass: either it moves
// the position less than kStepTolPx (and sigma less than kStepTolSigma), or its length in
// the metric of the Fisher information (d^T H d = g^T d, the predicted chi2 decrease) is
// below kStepTolChi2, i.e. the step is under 0.1 of the 1-sigma error ellipsoid. The error
// left is the next step, a fraction (the convergence rate, 0.1-0.3 here) of that: it adds
// < 0.1% to the variance.
constexpr double kStepTolPx = 1e-3;
constexpr double kStepTolSigma = 1e-2;
constexpr double kStepTolChi2 = 0.1 * 0.1;
constexpr double kMaxRate2 = 0.25;  // contraction r < 0.5 per step before r is trusted

// A star smeared by L px during the exposure (shorter than a streak) and fitted with the round
// PSF: its image has second moments s0^2 + L^2/12 along the smear and s0^2 across, and the round
// fit's sigma s sits in between, s^2 ~ s0^2 + L^2/24. The Fisher information of the round
// model along the smear is then that of a profile narrower than the star's: the variance along
// it is short by (s0^2 + L^2/12) / s^2 = 1 + L^2 / (24 s^2) (measured: tests/detect/
// test_blurred_stars.cpp; 1.15 at L = 1.9 px, s0 = 1 px). Across, the model's profile is wider
// than the star's, but the mis-specified fit does not reach the narrower profile's precision
// either (measured 0.95-1.0): left as it is, on the safe side.
void widenAlongSmear(const Vec2& smear, double s, Mat2& cov) {
  const double L2 = smear.squaredNorm();
  if (!(L2 > 0) || !(s > 0)) return;
  const Vec2 u = smear / std::sqrt(L2);
  cov += (L2 / (24.0 * s * s)) * u.dot(cov * u) * (u * u.transpose());
}

// Start of the fit: the caller's first position when it is inside the window (the centre of
// light of the pixels above the threshold: 0.10 px from the solution on the real frames,
// where the window's CoG, moved by the noise of every pixel, is 0.21 px off; 2.75 instead of
// 3.15 evaluations per star), else the background-subtracted centre of gravity (seed 004
// eq. 4.1); the flux is the window's sum. Also copies the pixels into `work`.
bool startFit(const StarPatch& P, Work& work, V5& p, double& peak, std::string* reason) {
  const cv::Mat1f& v = P.values;
  const double ox = P.origin.x, oy = P.origin.y;
  const Work::Sums start = work.reset(P);
  const double sw = start.sw, sx = start.sx, sy = start.sy;
  peak = start.peak;
  if (!(sw > 0)) {
    if (reason) *reason = "no flux above background";
    return false;
  }
  const bool guess_inside = P.guess.x() >= ox && P.guess.y() >= oy &&
                            P.guess.x() <= ox + v.cols - 1 && P.guess.y() <= oy + v.rows - 1;
  const V5 p0 = {guess_inside ? P.guess.x() : ox + sx / sw,
                 guess_inside ? P.guess.y() : oy + sy / sw, std::max(sw, peak), P.background,
                 std::clamp(P.psf_sigma, 0.4, 10.0)};
  std::copy(p0, p0 + 5, p);
  if (p[0] < ox - 0.5 || p[1] < oy - 0.5 || p[0] > ox + v.cols - 0.5 ||
      p[1] > oy + v.rows - 0.5) {
    if (reason) *reason = "centroid left the window";
    return false;
  }
  if (start.unsaturated < 7) {
    if (reason) *reason = "too few unsaturated pixels to fit";
    return false;
  }
  return true;
}

// Levenberg-Marquardt from p; N holds the normal equations at the last accepted estimate.
class LmFit {
 public:
  LmFit(const StarPatch& P, Work& work, V5& p)
      : P_(P), work_(work), p_(p), w_cur_(work.w_cur.data()), w_trial_(work.w_trial.data()) {}

  void run();
  const Normal& normal() const { return *N_; }
  // The factor of the converged step's normal equations, for the covariance when their
  // damping is negligible (<= 1e-4 relative: the covariance is then off by <= 0.01 %).
  Ldl5& factor() { return factor_; }
  bool converged() const { return have_converged_; }

 private:
  bool stepConverged(const V5& d, double gd, double gd_prev) const;

  const StarPatch& P_;
  Work& work_;
  V5& p_;
  double* w_cur_;
  double* w_trial_;
  // The normal equations at the estimate (N) and at a trial (T): swapped, not copied.
  Normal nbuf_[2];
  Normal* N_ = &nbuf_[0];
  Normal* T_ = &nbuf_[1];
  Ldl5 factor_;  // of the damped normal equations of the last trial
  bool have_converged_ = false;
};

// Error left after taking d: the next step, r * d with r^2 ~ gd / gd_prev (the measured
// contraction of the last step, trusted once it is clearly contracting).
bool LmFit::stepConverged(const V5& d, double gd, double gd_prev) const {
  const double rate2 = gd_prev > 0 ? gd / gd_prev : 1.0;
  return (d[0] * d[0] + d[1] * d[1] < kStepTolPx * kStepTolPx &&
          std::abs(d[4]) < kStepTolSigma) ||
         gd < kStepTolChi2 || (rate2 < kMaxRate2 && gd * rate2 < kStepTolChi2);
}

void LmFit::run() {
  V5& p = p_;
  have_converged_ = false;
  evaluate(P_, p, work_, w_cur_, w_trial_ /* no previous weights: chi2_prev unused */, *N_);
  double lambda = 1e-3;
  double gd_prev = 0;  // predicted chi2 decrease of the last accepted step
  for (int it = 0; it < kMaxTrials; ++it) {
    M5 A;
    std::copy(&N_->H[0][0], &N_->H[0][0] + 25, &A[0][0]);
    for (int k = 0; k < 5; ++k) A[k][k] *= 1.0 + lambda;
    V5 d;
    if (!factorLdl5(A, factor_)) {
      lambda *= 10;
      if (lambda > 1e8) break;
      continue;
    }
    ldlSolve5(factor_, N_->g, d);
    if (!finite5(d)) break;
    V5 q;
    for (int k = 0; k < 5; ++k) q[k] = p[k] + d[k];
    q[4] = std::clamp(q[4], 0.25, 20.0);
    double gd = 0;
    for (int k = 0; k < 5; ++k) gd += N_->g[k] * d[k];
    if (stepConverged(d, gd, gd_prev)) {
      std::copy(q, q + 5, p);  // converged: the last step is too small to need checking
      have_converged_ = lambda <= 1e-4;
      break;
    }
    evaluate(P_, q, work_, w_trial_, w_cur_, *T_);
    // Accept when the chi2 with the current weights does not grow (a fixed weighted
    // least-squares problem on both sides of the comparison).
    if (T_->chi2_prev <= N_->chi2_self + 1e-12) {
      std::copy(q, q + 5, p);
      std::swap(N_, T_);
      std::swap(w_cur_, w_trial_);
      gd_prev = gd;
      lambda = std::max(lambda * 0.1, 1e-7);
    } else {
      lambda *= 10;
      if (lambda > 1e8) break;
    }
  }
}

// Covariance: the inverse of the Fisher information J^T W J (Cramer-Rao), columns x, y, F;
// false when it is singular.
bool fisherCovariance(LmFit& fit, const StarPatch& P, const V5& p, double peak, Centroid& out,
                      std::string* reason) {
  Ldl5& L = fit.factor();
  V5 cx, cy, cf;
  const V5 ex = {1, 0, 0, 0, 0}, ey = {0, 1, 0, 0, 0}, ef = {0, 0, 1, 0, 0};
  if (!fit.converged() && !factorLdl5(fit.normal().H, L)) {
    if (reason) *reason = "PSF fit singular";
    return false;
  }
  ldlSolve5(L, ex, cx);
  ldlSolve5(L, ey, cy);
  ldlSolve5(L, ef, cf);
  if (!finite5(cx) || !finite5(cy) || !finite5(cf) || !(cx[0] > 0) || !(cy[1] > 0) ||
      !(cf[2] > 0)) {
    if (reason) *reason = "PSF fit singular";
    return false;
  }
  out.px = Vec2(p[0], p[1]);
  out.cov_px << cx[0], 0.5 * (cx[1] + cy[0]), 0.5 * (cx[1] + cy[0]), cy[1];
  widenAlongSmear(P.smear, p[4], out.cov_px);
  out.flux = p[2];
  out.peak = peak;
  out.snr = p[2] / std::sqrt(cf[2]);
  return true;
}

class GaussFitCentroider final : public Centroider {
 public:
  std::string name() const override { return "gauss"; }

 private:
  bool doCentroid(const StarPatch& P, Centroid& out, std::string* reason) const override {
    const cv::Mat1f& v = P.values;
    const double ox = P.origin.x, oy = P.origin.y;
    thread_local Work work;
    V5 p;
    double peak = 0;
    if (!startFit(P, work, p, peak, reason)) return false;
    LmFit fit(P, work, p);
    fit.run();
    // A pixel the model cannot explain (a hot pixel, a cosmic ray) pulls the fit towards it:
    // drop the worst pixel beyond kOutlierSigma and fit again, a few times at most.
    // Looked for only when the fit's chi2 is high enough to hold one: an 8-sigma pixel adds
    // 64 to it, a good fit gives n - 5 +- sqrt(2 (n - 5)); the search costs a pass.
    for (int dropped = 0;
         P.reject_spikes && dropped < kMaxOutliers && finite5(p) &&
         fit.normal().chi2_self > work.usable() - 5 + 0.5 * kOutlierSigma * kOutlierSigma &&
         dropOutlier(P, p, work);
         ++dropped)
      fit.run();
    if (!finite5(p) || !(p[2] > 0) || p[0] < ox - 0.5 || p[1] < oy - 0.5 ||
        p[0] > ox + v.cols - 0.5 || p[1] > oy + v.rows - 0.5 || p[4] >= 20.0) {
      if (reason) *reason = "PSF fit diverged";
      return false;
    }
    return fisherCovariance(fit, P, p, peak, out, reason);
  }
};

}  // namespace

std::unique_ptr<Centroider> makeGaussFitCentroider() {
  return std::make_unique<GaussFitCentroider>();
}

}  // namespace st

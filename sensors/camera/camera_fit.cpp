#include "sensors/camera/camera_fit.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <Eigen/Cholesky>
#include <Eigen/LU>

#include "common/chi_square.hpp"
#include "common/errors.hpp"

namespace st {

CameraParams cameraParams(const CameraModel& cam) {
  CameraParams t;
  t << cam.fx(), cam.fy(), cam.cx(), cam.cy(), cam.distortion().k1, cam.distortion().k2;
  return t;
}

CameraModel withCameraParams(const CameraModel& base, const CameraParams& t) {
  Distortion d = base.distortion();
  d.k1 = t[kK1];
  d.k2 = t[kK2];
  return CameraModel(base.width(), base.height(), t[kFx], t[kFy], t[kCx], t[kCy], d);
}

CameraPrior CameraPrior::around(const CameraModel& cam, double sigma_focal_rel,
                                double sigma_pp_px, double sigma_k) {
  CameraPrior p;
  p.mean = cameraParams(cam);
  const auto info = [](double s) { return s > 0 ? 1.0 / (s * s) : 0.0; };
  p.information(kFx, kFx) = info(sigma_focal_rel * cam.fx());
  p.information(kFy, kFy) = info(sigma_focal_rel * cam.fy());
  p.information(kCx, kCx) = p.information(kCy, kCy) = info(sigma_pp_px);
  p.information(kK1, kK1) = p.information(kK2, kK2) = info(sigma_k);
  return p;
}

CameraPrior CameraFitResult::posterior() const {
  CameraPrior p;
  p.mean = theta;
  // Fixed parameters (zero covariance rows) stay unconstrained by this fit's posterior.
  std::vector<int> free;
  for (int i = 0; i < kNumCameraParams; ++i)
    if (cov(i, i) > 0) free.push_back(i);
  const int n = static_cast<int>(free.size());
  Eigen::MatrixXd c(n, n);
  for (int a = 0; a < n; ++a)
    for (int b = 0; b < n; ++b) c(a, b) = cov(free[a], free[b]);
  const Eigen::MatrixXd info = c.ldlt().solve(Eigen::MatrixXd::Identity(n, n));
  for (int a = 0; a < n; ++a)
    for (int b = 0; b < n; ++b) p.information(free[a], free[b]) = info(a, b);
  return p;
}

namespace {

/// The free directions of the intrinsics: theta = theta0 + M * delta. Columns are scaled so
/// that delta is well conditioned (focal: relative; principal point: pixels; k: unitless).
Eigen::MatrixXd freeDirections(const CameraParams& theta0, const CameraFitSpec& spec) {
  std::vector<CameraParams> cols;
  const auto unit = [](int i, double s) {
    CameraParams c = CameraParams::Zero();
    c[i] = s;
    return c;
  };
  if (spec.focal && spec.aspect) {
    cols.push_back(unit(kFx, theta0[kFx]));
    cols.push_back(unit(kFy, theta0[kFy]));
  } else if (spec.focal) {
    CameraParams c = CameraParams::Zero();
    c[kFx] = theta0[kFx];
    c[kFy] = theta0[kFy];
    cols.push_back(c);
  }
  if (spec.principal_point) cols.push_back(unit(kCx, 1.0)), cols.push_back(unit(kCy, 1.0));
  if (spec.radial_terms >= 1) cols.push_back(unit(kK1, 1.0));
  if (spec.radial_terms >= 2) cols.push_back(unit(kK2, 1.0));
  Eigen::MatrixXd M(kNumCameraParams, static_cast<int>(cols.size()));
  for (std::size_t i = 0; i < cols.size(); ++i) M.col(static_cast<int>(i)) = cols[i];
  return M;
}

/// d(pixel)/d(theta) at camera-frame direction v (analytic: pixel = f * distort(xn) + c).
Eigen::Matrix<double, 2, kNumCameraParams> intrinsicsJacobian(const CameraModel& cam,
                                                              const Vec3& v) {
  const double x = v.x() / v.z(), y = v.y() / v.z(), r2 = x * x + y * y;
  const Distortion& d = cam.distortion();
  const double radial = 1 + r2 * (d.k1 + r2 * (d.k2 + r2 * d.k3));
  const double xd = x * radial + 2 * d.p1 * x * y + d.p2 * (r2 + 2 * x * x);
  const double yd = y * radial + d.p1 * (r2 + 2 * y * y) + 2 * d.p2 * x * y;
  Eigen::Matrix<double, 2, kNumCameraParams> J = Eigen::Matrix<double, 2, kNumCameraParams>::Zero();
  J(0, kFx) = xd;
  J(1, kFy) = yd;
  J(0, kCx) = 1;
  J(1, kCy) = 1;
  J(0, kK1) = cam.fx() * x * r2;
  J(1, kK1) = cam.fy() * y * r2;
  J(0, kK2) = cam.fx() * x * r2 * r2;
  J(1, kK2) = cam.fy() * y * r2 * r2;
  return J;
}

/// d(pixel)/d(v) for v in the camera frame: pixel Jacobian times d(x/z, y/z)/dv.
Eigen::Matrix<double, 2, 3> directionJacobian(const CameraModel& cam, const Vec3& v) {
  Eigen::Matrix<double, 2, 3> dn;
  const double iz = 1.0 / v.z();
  dn << iz, 0, -v.x() * iz * iz, 0, iz, -v.y() * iz * iz;
  return cam.pixelJacobian(v) * dn;
}

/// One Levenberg-Marquardt problem over [delta (p), dphi_1 .. dphi_N (3 each)].
class FitProblem {
 public:
  FitProblem(const CameraModel& start, const std::vector<FrameStars>& frames,
             const std::vector<std::vector<char>>& use, const CameraFitSpec& spec,
             const CameraPrior* prior)
      : base_(start),
        frames_(frames),
        use_(use),
        prior_(prior),
        theta0_(cameraParams(start)),
        M_(freeDirections(theta0_, spec)),
        p_(static_cast<int>(M_.cols())),
        n_(p_ + 3 * static_cast<int>(frames.size())) {
    for (const FrameStars& f : frames) q0_.push_back(f.q_ic.normalized());
  }

  int unknowns() const { return n_; }
  int freeIntrinsics() const { return p_; }
  const Eigen::MatrixXd& directions() const { return M_; }

  CameraParams theta(const Eigen::VectorXd& x) const { return theta0_ + M_ * x.head(p_); }
  Quat attitude(const Eigen::VectorXd& x, std::size_t j) const {
    return (q0_[j] * quatExp(x.segment<3>(p_ + 3 * static_cast<int>(j)))).normalized();
  }

  /// Residual chi2 (prior excluded) and the normal equations at x; false when the camera
  /// is invalid or a star falls behind it.
  bool evaluate(const Eigen::VectorXd& x, double& chi2, double& prior_cost, Eigen::MatrixXd* H,
                Eigen::VectorXd* g) const {
    CameraModel cam;
    try {
      cam = withCameraParams(base_, theta(x));
    } catch (const InputError&) {
      return false;
    }
    chi2 = 0;
    if (H) H->setZero(n_, n_), g->setZero(n_);
    Eigen::MatrixXd Jrow(2, n_);
    for (std::size_t j = 0; j < frames_.size(); ++j) {
      const Mat3 R_ci = attitude(x, j).toRotationMatrix().transpose();
      const int col = p_ + 3 * static_cast<int>(j);
      const FrameStars& f = frames_[j];
      for (std::size_t k = 0; k < f.size(); ++k) {
        if (!use_[j][k]) continue;
        const Vec3 v = R_ci * f.u_i[k];
        const auto px = cam.vectorToPixel(v);
        if (!px) return false;
        const double w = 1.0 / f.sigma_px[k];
        const Vec2 r = (*px - f.px[k]) * w;
        chi2 += r.squaredNorm();
        if (!H) continue;
        Jrow.setZero();
        Jrow.leftCols(p_) = intrinsicsJacobian(cam, v) * M_ * w;
        // v = Exp(-dphi) v0: dv/d(dphi) = [v]x.
        Jrow.middleCols<3>(col) = directionJacobian(cam, v) * skew(v) * w;
        *H += Jrow.transpose() * Jrow;
        *g += Jrow.transpose() * r;
      }
    }
    prior_cost = 0;
    if (prior_) {
      const CameraParams e = theta(x) - prior_->mean;
      prior_cost = e.dot(prior_->information * e);
      if (H) {
        H->topLeftCorner(p_, p_) += M_.transpose() * prior_->information * M_;
        g->head(p_) += M_.transpose() * prior_->information * e;
      }
    }
    return true;
  }

 private:
  const CameraModel& base_;
  const std::vector<FrameStars>& frames_;
  const std::vector<std::vector<char>>& use_;
  const CameraPrior* prior_;
  CameraParams theta0_;
  Eigen::MatrixXd M_;
  int p_, n_;
  std::vector<Quat> q0_;
};

/// Levenberg-Marquardt (Marquardt's diagonal scaling) from x = 0. Returns the iterations
/// used, -1 when the start itself cannot be evaluated.
int minimise(const FitProblem& prob, int max_iterations, Eigen::VectorXd& x) {
  const int n = prob.unknowns();
  x.setZero(n);
  Eigen::MatrixXd H;
  Eigen::VectorXd g;
  double chi2 = 0, pc = 0;
  if (!prob.evaluate(x, chi2, pc, &H, &g)) return -1;
  double cost = chi2 + pc, lambda = 1e-4;
  int it = 0;
  for (; it < max_iterations; ++it) {
    bool improved = false;
    for (int tries = 0; tries < 12 && !improved; ++tries) {
      Eigen::MatrixXd A = H;
      A.diagonal() += lambda * H.diagonal().cwiseMax(1e-12);
      const Eigen::VectorXd step = A.ldlt().solve(-g);
      if (!step.allFinite()) {
        lambda *= 10;
        continue;
      }
      const Eigen::VectorXd xn = x + step;
      double c2 = 0, p2 = 0;
      if (prob.evaluate(xn, c2, p2, nullptr, nullptr) && c2 + p2 < cost) {
        const double gain = cost - (c2 + p2);
        x = xn;
        cost = c2 + p2;
        lambda = std::max(lambda / 10, 1e-12);
        prob.evaluate(x, chi2, pc, &H, &g);
        improved = true;
        if (gain < 1e-10 * std::max(1.0, cost)) return it + 1;
      } else {
        lambda *= 10;
      }
    }
    if (!improved) break;  // no step lowers the cost: at the minimum (to rounding)
  }
  return it;
}

/// Pixel residual norms of the used stars at x, per frame.
std::vector<std::vector<double>> residualNorms(const CameraModel& cam,
                                              const std::vector<FrameStars>& frames,
                                              const std::vector<Quat>& q_ic) {
  std::vector<std::vector<double>> out(frames.size());
  for (std::size_t j = 0; j < frames.size(); ++j) {
    const Mat3 R_ci = q_ic[j].toRotationMatrix().transpose();
    for (std::size_t k = 0; k < frames[j].size(); ++k) {
      const auto px = cam.vectorToPixel(R_ci * frames[j].u_i[k]);
      out[j].push_back(px ? (*px - frames[j].px[k]).norm() : 1e9);
    }
  }
  return out;
}

void rmsOf(const std::vector<std::vector<double>>& r, const std::vector<std::vector<char>>& use,
           double& all, std::vector<double>& per_frame) {
  double s = 0;
  long n = 0;
  per_frame.assign(r.size(), 0.0);
  for (std::size_t j = 0; j < r.size(); ++j) {
    double sj = 0;
    long nj = 0;
    for (std::size_t k = 0; k < r[j].size(); ++k)
      if (use[j][k]) sj += r[j][k] * r[j][k], ++nj;
    per_frame[j] = nj > 0 ? std::sqrt(sj / nj) : 0.0;
    s += sj, n += nj;
  }
  all = n > 0 ? std::sqrt(s / n) : 0.0;
}

}  // namespace

CameraFitResult fitCamera(const CameraModel& start, const std::vector<FrameStars>& frames,
                          const CameraFitSpec& spec, const CameraPrior* prior,
                          const CameraFitOptions& options) {
  CameraFitResult res;
  res.camera = start;
  res.spec = spec;
  std::vector<std::vector<char>> use(frames.size());
  for (std::size_t j = 0; j < frames.size(); ++j) {
    use[j].assign(frames[j].size(), 1);
    res.q_ic.push_back(frames[j].q_ic.normalized());
  }
  Eigen::VectorXd x;
  for (int round = 0; round < 4; ++round) {
    FitProblem prob(start, frames, use, spec, prior);
    int stars = 0;
    for (const auto& u : use) stars += static_cast<int>(std::count(u.begin(), u.end(), 1));
    res.stars = stars;
    res.dof = 2 * stars - prob.unknowns();
    // Without a prior the frames' rotations and the intrinsics need more equations than
    // unknowns; a prior adds equations for the intrinsics only.
    if (2 * stars < prob.unknowns() + (prior ? 0 : 1) || stars < 2 * static_cast<int>(frames.size())) {
      res.ok = false;
      res.reason = std::to_string(stars) + " stars are too few to fit " +
                   std::to_string(prob.freeIntrinsics()) + " camera parameters and " +
                   std::to_string(frames.size()) + " attitude(s)";
      return res;
    }
    res.iterations += std::max(0, minimise(prob, options.max_iterations, x));
    Eigen::MatrixXd H;
    Eigen::VectorXd g;
    double chi2 = 0, pc = 0;
    if (!prob.evaluate(x, chi2, pc, &H, &g)) {
      res.ok = false;
      res.reason = "the fitted camera is not valid (a star behind it or a non-positive focal length)";
      return res;
    }
    const Eigen::LDLT<Eigen::MatrixXd> ldlt(H);
    const Eigen::MatrixXd Hinv = ldlt.solve(Eigen::MatrixXd::Identity(H.rows(), H.cols()));
    if (ldlt.info() != Eigen::Success || !Hinv.allFinite() || (Hinv.diagonal().array() <= 0).any()) {
      res.ok = false;
      res.reason = "the camera parameters are not determined by these stars (singular fit)";
      return res;
    }
    const int p = prob.freeIntrinsics();
    res.theta = prob.theta(x);
    res.cov = prob.directions() * Hinv.topLeftCorner(p, p) * prob.directions().transpose();
    res.chi2 = chi2;
    for (std::size_t j = 0; j < frames.size(); ++j) res.q_ic[j] = prob.attitude(x, j);
    res.camera = withCameraParams(start, res.theta);
    if (options.outlier_sigma <= 0) break;
    // Drop the stars beyond outlier_sigma (normalised by their sigma and the fit's excess
    // scatter) and fit again; stop when none is dropped.
    const double scale = std::sqrt(std::max(1.0, res.chi2 / std::max(1, res.dof)));
    const auto r = residualNorms(res.camera, frames, res.q_ic);
    int dropped = 0;
    for (std::size_t j = 0; j < frames.size(); ++j)
      for (std::size_t k = 0; k < frames[j].size(); ++k)
        if (use[j][k] && r[j][k] / (frames[j].sigma_px[k] * scale) > options.outlier_sigma)
          use[j][k] = 0, ++dropped;
    if (dropped == 0) break;
    res.outliers += dropped;
  }
  {
    // "Before": the start camera at its own best attitudes (a fit with nothing free).
    CameraFitSpec none;
    none.focal = false;
    std::vector<Quat> q0;
    FitProblem prob(start, frames, use, none, nullptr);
    Eigen::VectorXd x0;
    minimise(prob, options.max_iterations, x0);
    for (std::size_t j = 0; j < frames.size(); ++j) q0.push_back(prob.attitude(x0, j));
    rmsOf(residualNorms(start, frames, q0), use, res.rms_before_px, res.frame_rms_before_px);
  }
  rmsOf(residualNorms(res.camera, frames, res.q_ic), use, res.rms_after_px, res.frame_rms_after_px);
  res.used = std::move(use);
  res.ok = true;
  return res;
}

CameraFitResult fitCameraChoosingRadial(const CameraModel& start,
                                        const std::vector<FrameStars>& frames,
                                        const CameraFitSpec& spec, const CameraPrior* prior,
                                        const CameraFitOptions& options, double alpha) {
  CameraFitSpec s = spec;
  s.radial_terms = 0;
  CameraFitResult best = fitCamera(start, frames, s, prior, options);
  const double threshold = chiSquareQuantile(1 - alpha, 1);
  for (int terms = 1; terms <= spec.radial_terms && best.ok; ++terms) {
    s.radial_terms = terms;
    CameraFitResult next = fitCamera(start, frames, s, prior, options);
    if (!next.ok || best.chi2 - next.chi2 <= threshold) break;
    best = std::move(next);
  }
  return best;
}

double modelErrorSigmaPx(const CameraFitResult& fit, const std::vector<FrameStars>& frames) {
  if (!fit.ok || fit.dof <= 0 || fit.chi2 <= fit.dof) return 0.0;
  const auto r = residualNorms(fit.camera, frames, fit.q_ic);
  const auto chi2With = [&](double s2) {
    double c = 0;
    for (std::size_t j = 0; j < frames.size(); ++j)
      for (std::size_t k = 0; k < frames[j].size(); ++k)
        if (fit.used[j][k])
          c += r[j][k] * r[j][k] / (frames[j].sigma_px[k] * frames[j].sigma_px[k] + s2);
    return c;
  };
  // chi2With decreases monotonically in s2: bisect chi2With(s2) = dof.
  double lo = 0, hi = 1;
  while (chi2With(hi) > fit.dof && hi < 1e8) hi *= 4;
  for (int i = 0; i < 100; ++i) {
    const double mid = 0.5 * (lo + hi);
    (chi2With(mid) > fit.dof ? lo : hi) = mid;
  }
  return std::sqrt(0.5 * (lo + hi));
}

std::string describeDiscrepancy(const CameraFitResult& fit, const CameraModel& reference,
                                const std::string& name, double n_sigma) {
  if (!fit.ok) return "";
  const CameraParams ref = cameraParams(reference);
  std::string out;
  char b[200];
  const auto add = [&](const char* s) { out += (out.empty() ? "" : "; ") + std::string(s); };
  const double rel = fit.theta[kFx] / ref[kFx] - 1, rel_sigma = fit.sigma(kFx) / ref[kFx];
  if (rel_sigma > 0 && std::abs(rel) > n_sigma * rel_sigma) {
    std::snprintf(b, sizeof b, "focal length appears %.2f %% %s than %s (+-%.2f %%)",
                  std::abs(rel) * 100, rel > 0 ? "longer" : "shorter", name.c_str(),
                  rel_sigma * 100);
    add(b);
  }
  for (int i : {kCx, kCy}) {
    const double d = fit.theta[i] - ref[i];
    if (fit.sigma(CameraParam(i)) > 0 && std::abs(d) > n_sigma * fit.sigma(CameraParam(i))) {
      std::snprintf(b, sizeof b, "%s %+.1f px from %s (+-%.1f px)", i == kCx ? "cx" : "cy", d,
                    name.c_str(), fit.sigma(CameraParam(i)));
      add(b);
    }
  }
  for (int i : {kK1, kK2}) {
    const double d = fit.theta[i] - ref[i];
    if (fit.sigma(CameraParam(i)) > 0 && std::abs(d) > n_sigma * fit.sigma(CameraParam(i))) {
      std::snprintf(b, sizeof b, "%s = %.4g (+-%.2g), %s has %.4g", i == kK1 ? "k1" : "k2",
                    fit.theta[i], fit.sigma(CameraParam(i)), name.c_str(), ref[i]);
      add(b);
    }
  }
  return out;
}

}  // namespace st

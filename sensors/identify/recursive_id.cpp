#include "sensors/identify/recursive_id.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <chrono>
#include <cmath>

#include "common/conventions.hpp"

namespace st {

namespace {
using Clock = std::chrono::steady_clock;
double seconds(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}
}  // namespace

RecursiveIdentifier::RecursiveIdentifier(const StarDatabase& db, const CameraModel& camera,
                                         RecursiveIdOptions o)
    : db_(db),
      camera_(camera),
      opts_(std::move(o)),
      detector_(opts_.detect),
      half_diagonal_fov_(camera.halfDiagonalFov()),
      sigma_c_px_(opts_.centroid_sigma_px) {}

void RecursiveIdentifier::cameraChanged(double model_error_px) {
  half_diagonal_fov_ = camera_.halfDiagonalFov();
  sigma_c_px_ = std::hypot(opts_.centroid_sigma_px, model_error_px);
  model_error_px_ = model_error_px;
}

Mat2 RecursiveIdentifier::centroidCovariance(const Mat2& cov_px) const {
  const double floor2 = opts_.centroid_sigma_px * opts_.centroid_sigma_px;
  Mat2 c = floor2 * Mat2::Identity();
  if (cov_px.allFinite()) {
    const Eigen::SelfAdjointEigenSolver<Mat2> es(cov_px);
    const Vec2 l = es.eigenvalues().cwiseMax(floor2);
    c = es.eigenvectors() * l.asDiagonal() * es.eigenvectors().transpose();
  }
  return c + model_error_px_ * model_error_px_ * Mat2::Identity();
}

void RecursiveIdentifier::predictCandidates(const CameraPrediction& pred) {
  const Mat3 R_ic = pred.q_ic.toRotationMatrix();
  // sqrt(trace) bounds the largest 1-sigma of the attitude (cheaper than an eigen solve).
  const double att_sigma = std::sqrt(std::max(0.0, pred.cov_cam.trace()));
  // Seed 002: the cone of the FOV + the attitude uncertainty.
  db_.coneQuery(R_ic.col(2), half_diagonal_fov_ + 3.0 * att_sigma, cone_);
  candidates_.clear();
  for (uint32_t i : cone_) {
    const Vec3 v = R_ic.transpose() * db_.stars()[i].u_i;
    if (v.z() <= 0) continue;
    const auto px = camera_.vectorToPixel(v);
    if (!px || !camera_.isPixelInImage(*px, 0.0)) continue;
    Candidate c;
    c.star_index = i;
    c.v_cam = v;
    c.px = *px;
    candidates_.push_back(c);
  }
  // The blend screen: stars too faint for the database still put light into its windows.
  db_.screenConeQuery(R_ic.col(2), half_diagonal_fov_ + 3.0 * att_sigma, cone_);
  screen_.clear();
  for (uint32_t i : cone_) {
    const ScreenStar& s = db_.screenStars()[i];
    const Vec3 v = R_ic.transpose() * s.u_i;
    if (v.z() <= 0) continue;
    if (const auto px = camera_.vectorToPixel(v)) screen_.push_back({*px, relativeFlux(s.mag)});
  }
}

bool RecursiveIdentifier::blended(const Candidate& c, const Vec2& blur) const {
  // The centroid window of a star is a square of half-size 2.5 psf + blur/2 around its
  // image's middle (centroidWindows), and another star's light reaches 3 psf beyond its own
  // streak (o.px +- blur/2). A star is windowed only if no other catalog star's light falls
  // into its window: for a streak that is a box of ~(blur + 6 psf) around it, not a fixed
  // radius (streaks of neighbours overlap along the streak direction and pull the centre of
  // gravity by flux ratio x distance). PSF sigma as the detector assumes it.
  const double psf = opts_.detect.psfSigmaGuess();
  const double blend2 = opts_.blend_separation_px * opts_.blend_separation_px;
  const double hc = std::ceil(2.5 * psf + 0.5 * blur.norm());
  const double reach_x = hc + 0.5 * std::abs(blur.x()) + 3.0 * psf;
  const double reach_y = hc + 0.5 * std::abs(blur.y()) + 3.0 * psf;
  for (const Candidate& o : candidates_) {
    if (&o == &c) continue;
    const Vec2 d = o.px - c.px;
    if (d.squaredNorm() < blend2 || (std::abs(d.x()) < reach_x && std::abs(d.y()) < reach_y))
      return true;
  }
  return screenedOut(c, reach_x, reach_y);
}

bool RecursiveIdentifier::screenedOut(const Candidate& c, double reach_x, double reach_y) const {
  // A neighbour of relative flux f whose light falls into the window moves the centre of
  // gravity by f / (1 + f) of their separation; a catalog star's neighbour excludes it
  // outright (above), a fainter one only when that pull matters against the centroid noise.
  const double flux_c = relativeFlux(db_.stars()[c.star_index].mag);
  const double max_pull = opts_.screen_pull_sigma * sigma_c_px_;
  const double blend2 = opts_.blend_separation_px * opts_.blend_separation_px;
  for (const ScreenImage& o : screen_) {
    const Vec2 d = o.px - c.px;
    if (d.squaredNorm() >= blend2 && (std::abs(d.x()) >= reach_x || std::abs(d.y()) >= reach_y))
      continue;
    const double f = o.flux / flux_c;
    if (f / (1 + f) * d.norm() > max_pull) return true;
  }
  return false;
}

void RecursiveIdentifier::placeWindows(const CameraPrediction& pred) {
  // The brightest stars (cone order = brightest first) away from the border and from blends.
  windows_.clear();
  windowed_.clear();
  const double sigma_c2 = sigma_c_px_ * sigma_c_px_;
  for (Candidate& c : candidates_) {
    if (int(windows_.size()) >= opts_.max_stars) break;
    if (!camera_.isPixelInImage(c.px, opts_.edge_margin_px)) continue;
    // Error model: v_true = Exp(-dtheta) v = v + [v]x dtheta (R_true = R Exp(dtheta)).
    c.H = attitudeJacobian(camera_, c.v_cam);
    const Vec2 blur = c.H * pred.rate_cam * opts_.exposure_s;
    if (blended(c, blur)) continue;
    c.cov_att_px = c.H * pred.cov_cam * c.H.transpose();
    PredictedStar p;
    p.px = c.px;
    p.cov_px = c.cov_att_px + sigma_c2 * Mat2::Identity();
    p.blur_px = blur;
    windows_.push_back(p);
    windowed_.push_back(&c);
  }
}

void RecursiveIdentifier::gate(RecursiveIdResult& out) {
  // Seed 002 step 5: |d| < 3 sqrt(2) sigma, as a Mahalanobis gate on H P H^T + C.
  const double gate2 = opts_.gate_sigma * opts_.gate_sigma;
  std::vector<double>& d2s = gated_d2_;
  d2s.clear();
  for (std::size_t k = 0; k < found_.size(); ++k) {
    if (!found_[k].centroid) continue;
    ++out.with_centroid;
    const Centroid& cen = *found_[k].centroid;
    const Vec2 d = cen.px - windowed_[k]->px;
    const Mat2 S = windowed_[k]->cov_att_px + centroidCovariance(cen.cov_px);
    const double d2 = d.dot(S.ldlt().solve(d));
    if (!(d2 <= gate2)) continue;
    // Two windows that caught the same blob: keep the closer prediction.
    bool duplicate = false;
    for (std::size_t j = 0; j < out.stars.size(); ++j) {
      if ((out.stars[j].px - cen.px).squaredNorm() < 1.0) {
        duplicate = true;
        if (d2 < d2s[j]) {
          out.stars[j] = cen;
          out.star_index[j] = windowed_[k]->star_index;
          d2s[j] = d2;
        }
        break;
      }
    }
    if (duplicate) continue;
    out.stars.push_back(cen);
    out.star_index.push_back(windowed_[k]->star_index);
    d2s.push_back(d2);
  }
  if (!opts_.drop_saturated) return;
  // Saturated stars' fits rest on their wings, and their errors exceed the covariance they
  // report: left out while at least min_stars others remain.
  std::size_t unsaturated = 0;
  for (const Centroid& c : out.stars) unsaturated += !(c.flags & kSaturated);
  if (int(unsaturated) < opts_.min_stars || unsaturated == out.stars.size()) return;
  std::size_t w = 0;
  for (std::size_t k = 0; k < out.stars.size(); ++k) {
    if (out.stars[k].flags & kSaturated) continue;
    out.stars[w] = out.stars[k];
    out.star_index[w] = out.star_index[k];
    ++w;
  }
  out.stars.resize(w);
  out.star_index.resize(w);
}

void RecursiveIdentifier::identify(const cv::Mat& image, const CameraPrediction& pred,
                                   RecursiveIdResult& out) {
  const auto t0 = Clock::now();
  out.stars.clear();
  out.star_index.clear();
  out.with_centroid = 0;
  out.detect_s = 0;
  predictCandidates(pred);
  placeWindows(pred);
  out.windows = static_cast<int>(windows_.size());
  const auto t1 = Clock::now();
  if (out.windows < opts_.min_stars) {
    out.status = RecursiveIdResult::Status::kTooFewPredicted;
    out.identify_s = seconds(t0, t1);
    return;
  }
  // Centroids in the windows only (seed 004 §4.2.3).
  detector_.centroidWindows(image, windows_, found_);
  const auto t2 = Clock::now();
  out.detect_s = seconds(t1, t2);
  gate(out);
  out.identify_s = seconds(t0, t1) + seconds(t2, Clock::now());
  out.status = int(out.stars.size()) < opts_.min_stars ? RecursiveIdResult::Status::kTooFewInGate
                                                       : RecursiveIdResult::Status::kOk;
}

}  // namespace st

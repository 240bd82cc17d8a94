#include "sensors/sim/star_renderer.hpp"

#include <algorithm>
#include <cmath>

#include "common/aberration.hpp"
#include "common/conventions.hpp"
#include "sensors/sim/psf.hpp"
#include "sensors/sim/random_streams.hpp"

namespace st {

AttitudeAt constantRateAttitude(const Quat& q_mid_ib, const Vec3& omega_body) {
  return [q_mid_ib, omega_body](double tau) { return q_mid_ib * quatExp(omega_body * tau); };
}

StarRenderer::StarRenderer(const CameraModel& camera, const SensorParams& sensor,
                           const StarSource& stars)
    : cam_(camera), sensor_(sensor), stars_(stars) {}

bool StarRenderer::isMissing(uint32_t id, const RenderOptions& opts) {
  if (opts.missing_star_fraction <= 0) return false;
  const uint64_t h = splitMix64(streamSeed(opts.missing_star_seed, RandomStream::kMissingStars) ^ id);
  return hashToUnit(h) < opts.missing_star_fraction;
}

namespace {
struct Source {
  Vec3 u_i;
  double electrons;
  double sigma_px;
  bool is_catalog;
  uint32_t id;
  double mag;
};
}  // namespace

std::vector<TrueStar> StarRenderer::render(const AttitudeAt& q_ib_at, cv::Mat& electrons,
                                           const RenderOptions& opts) const {
  CV_Assert(electrons.type() == CV_64FC1 && electrons.cols == cam_.width() &&
            electrons.rows == cam_.height());
  const double T = opts.exposure_s > 0 ? opts.exposure_s : sensor_.exposure_s;
  const double light = T / sensor_.exposure_s;  // starElectrons is for the sensor's exposure
  const Quat q_mid = q_ib_at(0.0), q_start = q_ib_at(-0.5 * T), q_end = q_ib_at(0.5 * T);
  const Mat3 R_mid = q_mid.toRotationMatrix();
  const Mat3 R_start = q_start.toRotationMatrix();
  const Mat3 R_end = q_end.toRotationMatrix();

  // Sources that can reach the image: the cone holding the image, widened by the rotation
  // during half the exposure and by the widest PSF.
  double max_sigma = sensor_.psf_sigma_px;
  for (const ExtraSource& e : opts.extras) max_sigma = std::max(max_sigma, e.sigma_px);
  const double half_turn = std::max(quatLog(canonical(q_mid.inverse() * q_start)).norm(),
                                    quatLog(canonical(q_mid.inverse() * q_end)).norm());
  const double radius = cam_.halfDiagonalFov() + half_turn + (6 * max_sigma + 2) * cam_.pixelScale();
  const Vec3 boresight_i = R_mid.col(2);
  stars_.query(boresight_i, std::min(radius, 0.49 * kPi), scratch_);

  const Vec3& v = opts.observer_velocity_km_s;
  auto seen = [&v](const Vec3& u) { return v.isZero() ? u : applyAberration(u, v); };
  std::vector<Source> sources;
  sources.reserve(scratch_.size() + opts.extras.size());
  for (const SkyStar& s : scratch_) {
    if (isMissing(s.id, opts)) continue;
    sources.push_back({seen(s.u_i), light * sensor_.starElectrons(s.mag), sensor_.psf_sigma_px, true, s.id, s.mag});
  }
  const double cos_r = std::cos(radius);
  for (const ExtraSource& e : opts.extras)
    if (e.u_i.dot(boresight_i) >= cos_r)
      sources.push_back({seen(e.u_i), light * sensor_.starElectrons(e.mag), e.sigma_px, false, 0, e.mag});

  // Sub-step count from the longest streak (start -> mid -> end) of any source.
  double max_len = 0;
  for (const Source& s : sources) {
    const auto a = cam_.vectorToPixel(R_start.transpose() * s.u_i);
    const auto m = cam_.vectorToPixel(R_mid.transpose() * s.u_i);
    const auto b = cam_.vectorToPixel(R_end.transpose() * s.u_i);
    if (a && m && b) max_len = std::max(max_len, (*m - *a).norm() + (*b - *m).norm());
  }
  const double spacing = opts.max_substep_sigma *
                        std::min(sensor_.psfSigmaX(), sensor_.psfSigmaY());
  const int n = std::clamp(static_cast<int>(std::ceil(max_len / spacing)), 1, opts.max_substeps);
  last_substeps_ = n;
  std::vector<Mat3> R_bi(static_cast<std::size_t>(n));  // inertial -> body at each sub-step
  for (int k = 0; k < n; ++k) {
    const double tau = n == 1 ? 0.0 : -0.5 * T + (k + 0.5) * T / n;
    R_bi[static_cast<std::size_t>(k)] = q_ib_at(tau).toRotationMatrix().transpose();
  }

  std::vector<TrueStar> truth;
  std::vector<Vec2> path(static_cast<std::size_t>(n));
  for (const Source& s : sources) {
    // The whole path, and its bounding box against the image grown by the PSF reach.
    double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
    bool ok = true;
    for (int k = 0; k < n && ok; ++k) {
      const auto p = cam_.vectorToPixel(R_bi[static_cast<std::size_t>(k)] * s.u_i);
      if (!p) {
        ok = false;
        break;
      }
      path[static_cast<std::size_t>(k)] = *p;
      x0 = std::min(x0, p->x()), x1 = std::max(x1, p->x());
      y0 = std::min(y0, p->y()), y1 = std::max(y1, p->y());
    }
    if (!ok) continue;
    const double reach = 6 * s.sigma_px + 1;
    if (x1 < -reach || y1 < -reach || x0 > cam_.width() - 1 + reach ||
        y0 > cam_.height() - 1 + reach)
      continue;
    const double share = s.electrons / n;
    // A source's sigma is in native pixels: binning narrows it along the binned axis.
    const double sx = s.sigma_px / sensor_.binning_x, sy = s.sigma_px / sensor_.binning_y;
    for (int k = 0; k < n; ++k)
      addGaussianStarXY(electrons, path[static_cast<std::size_t>(k)], share, sx, sy);
    if (!s.is_catalog) continue;
    const auto p_mid = cam_.vectorToPixel(R_mid.transpose() * s.u_i);
    if (p_mid && cam_.isPixelInImage(*p_mid)) truth.push_back({s.id, *p_mid, s.mag, s.electrons});
  }
  std::stable_sort(truth.begin(), truth.end(),
                   [](const TrueStar& a, const TrueStar& b) { return a.mag < b.mag; });
  return truth;
}

}  // namespace st

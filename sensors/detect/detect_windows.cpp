// Predictive windows (seed 004 §4.2.3): each predicted star is measured from a small window
// only, with the detector's centroiders and scratch buffers.
#include <algorithm>
#include <cmath>

#include "sensors/detect/detect_internal.hpp"

namespace st::detect_detail {

// One predictive window (seed 004 §4.2.3): background from the window's border ring, the
// brightest pixel inside, and the centroid in a PSF-sized window around it.
template <typename T>
void centroidWindow(const cv::Mat& grey, const PredictedStar& p, const DetectorOptions& opts,
                    double sat, const Centroider& main, const Centroider& cog, Scratch& s,
                    WindowResult& w) {
  const cv::Rect frame(0, 0, grey.cols, grey.rows);
  if (!p.px.allFinite() || p.px.x() < -0.5 || p.px.y() < -0.5 || p.px.x() > grey.cols - 0.5 ||
      p.px.y() > grey.rows - 0.5) {
    w.reason = "outside image";
    return;
  }
  const int h = windowHalfSize(p, opts);
  const int cx = static_cast<int>(std::lround(p.px.x())),
            cy = static_cast<int>(std::lround(p.px.y()));
  const cv::Rect win = cv::Rect(cx - h, cy - h, 2 * h + 1, 2 * h + 1) & frame;
  if (win.width < 3 || win.height < 3) {
    w.reason = "outside image";
    return;
  }
  // Background and noise from the window's border ring; peak inside (first maximum in
  // raster order).
  std::vector<float>& ring = s.ring;
  ring.resize(static_cast<std::size_t>(2 * win.width + 2 * (win.height - 2)));
  float* rp = ring.data();
  int best = -1;
  cv::Point pk;
  for (int y = win.y; y < win.y + win.height; ++y) {
    const T* row = grey.ptr<T>(y);
    // The row's maximum without branches (vectorised), its position only when it is a new
    // peak: a compare-and-remember per pixel mispredicts on noise.
    const int row_max = maxOf(row + win.x, win.width);
    if (row_max > best) {
      best = row_max;
      pk = {static_cast<int>(std::find(row + win.x, row + win.x + win.width, row_max) - row), y};
    }
    if (y == win.y || y == win.y + win.height - 1) {
      for (int x = win.x; x < win.x + win.width; ++x) *rp++ = static_cast<float>(row[x]);
    } else {
      *rp++ = static_cast<float>(row[win.x]);
      *rp++ = static_cast<float>(row[win.x + win.width - 1]);
    }
  }
  const double peak = best;
  double b, sb;
  robustLevelSigma(ring, b, sb);
  sb = std::max({sb, opts.read_noise_adu, 0.3});
  if (peak - b < opts.threshold_sigma * sb) {
    w.reason = "below threshold";
    return;
  }
  // Centroid window inside the search window: PSF radius plus half the streak around the
  // star's middle. The brightest pixel of a streak can be anywhere along it (noise decides),
  // so for a streak the middle is first located as the centre of the above-threshold pixels
  // within a full streak length of the peak; a window centred on the peak would cut off up
  // to half the streak and move the centroid by a quarter of its length.
  const double psf0 = opts.psfSigmaGuess();
  const double blur = p.blur_px.norm();
  const double thr = b + opts.threshold_sigma * sb;
  auto thresholdMoments = [&](const cv::Rect& r, int& area, Moments& mom) {
    // Branch-free (pixels below the threshold add zeros): whether a noise pixel is above
    // the threshold is a coin flip the branch predictor loses.
    area = 0;
    double sw = 0, sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0;
    for (int y = r.y; y < r.y + r.height; ++y) {
      const T* row = grey.ptr<T>(y);
      double rw = 0, rx = 0, rxx = 0;
      for (int x = r.x; x < r.x + r.width; ++x) {
        const double v = row[x];
        const bool above = v > thr;
        const double w = above ? v - b : 0.0;
        area += above;
        rw += w;
        rx += w * x;
        rxx += w * x * x;
      }
      sw += rw;
      sx += rx;
      sxx += rxx;
      sy += rw * y;
      syy += rw * y * y;
      sxy += rx * y;
    }
    mom = Moments();
    mom.sw = sw, mom.sx = sx, mom.sy = sy, mom.sxx = sxx, mom.syy = syy, mom.sxy = sxy;
  };
  const bool streak = blur > 2.0 * psf0;
  cv::Point centre = pk;
  int area = 0;
  Moments mom;
  // A tight prediction (tracking with a gyro) places a streak's middle better than its
  // pixels do: a faint streak breaks into fragments above the threshold, and the moments of
  // one fragment put the window on one end of the streak.
  const bool trust_prediction = streak && 3.0 * largestSigma(p.cov_px) <= psf0 + 0.25 * blur;
  if (trust_prediction) {
    centre = {cx, cy};
  } else if (streak) {
    const cv::Point anchor = p.anchor_at_px ? cv::Point(cx, cy) : pk;
    const int hs = static_cast<int>(std::ceil(2.5 * psf0 + blur));
    thresholdMoments(cv::Rect(anchor.x - hs, anchor.y - hs, 2 * hs + 1, 2 * hs + 1) & win, area,
                     mom);
    if (mom.sw > 0)
      centre = {static_cast<int>(std::lround(mom.sx / mom.sw)),
                static_cast<int>(std::lround(mom.sy / mom.sw))};
  }
  const int hc = static_cast<int>(std::ceil(2.5 * psf0 + 0.5 * blur));
  const Centroider& c = streak ? cog : main;  // a streak is not a round PSF: the CoG
                                              // measures its middle
  // A window off the streak's middle cuts the streak and pulls the CoG towards the window's
  // centre; re-centring on the last CoG converges to the middle (a few rounds for a streak
  // located from a fragment; a tight prediction needs none).
  const int rounds = streak && !trust_prediction ? 3 : 1;
  for (int round = 0; round < rounds; ++round) {
    const cv::Rect full(centre.x - hc, centre.y - hc, 2 * hc + 1, 2 * hc + 1);
    const cv::Rect cw = full & win;
    uint32_t flags = 0;
    if (peak >= sat) flags |= kSaturated;
    if ((full & frame).area() != full.area()) flags |= kTouchesEdge;
    double psf = psf0;
    if (streak) {
      flags |= kElongated;  // by construction; its moments would only say so again
    } else {
      thresholdMoments(cw, area, mom);
      double elong = 1;
      mom.shape(elong, psf);
      if (elong > opts.max_elongation) flags |= kElongated;
      if (opts.psf_sigma_px > 0) psf = opts.psf_sigma_px;
      psf = psf > 0 ? std::clamp(psf, 0.5, 5.0) : DetectorOptions::kAssumedPsfSigmaPx;
    }
    const Vec2 start = !streak && mom.sw > 0 ? Vec2(mom.sx / mom.sw, mom.sy / mom.sw)
                                             : Vec2(pk.x, pk.y);  // as in measureBlobs
    StarPatch patch = makePatch<T>(grey, cw, b, sb, sat, psf, start, opts, s.patch);
    patch.smear = p.blur_px;
    // Variance of the ring median: pi/2 sigma^2 / n for Gaussian noise.
    patch.background_var = 0.5 * M_PI * sb * sb / static_cast<double>(ring.size());
    Centroid star;
    std::string reason;
    if (!measure(c, cog, patch, star, &reason)) {
      if (round > 0) break;  // keep the last round's centroid
      w.reason = "not found: " + reason;
      return;
    }
    // One pixel above the threshold is not a star: the window's integrated flux must be as
    // significant as a detection (a faint streak spreads below it; its CoG is noise).
    if (star.snr < opts.threshold_sigma) {
      w.reason = "below threshold: SNR " + std::to_string(star.snr);
      w.centroid.reset();
      return;
    }
    star.area = area;
    star.flags = flags;
    w.centroid = star;
    const cv::Point next(static_cast<int>(std::lround(star.px.x())),
                         static_cast<int>(std::lround(star.px.y())));
    if (next == centre) break;
    centre = next;
  }
}

template void centroidWindow<uint8_t>(const cv::Mat&, const PredictedStar&, const DetectorOptions&,
                                      double, const Centroider&, const Centroider&, Scratch&,
                                      WindowResult&);
template void centroidWindow<uint16_t>(const cv::Mat&, const PredictedStar&,
                                       const DetectorOptions&, double, const Centroider&,
                                       const Centroider&, Scratch&, WindowResult&);

}  // namespace st::detect_detail

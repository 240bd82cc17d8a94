// Predictive windows (seed 004 §4.2.3): each predicted star is measured from a small window
// only, with the detector's centroiders and scratch buffers.
#include <algorithm>
#include <cmath>

#include "sensors/detect/detect_internal.hpp"
#include "sensors/detect/radiation_hits.hpp"

namespace st::detect_detail {

namespace {

// What the steps of one window share: the search window, its background level and noise
// from the border ring, its peak, and how the star is expected to look.
struct WindowScan {
  WindowScan(const cv::Mat& g, const PredictedStar& pr, const DetectorOptions& o)
      : grey(g), p(pr), opts(o), frame(0, 0, g.cols, g.rows) {}
  const cv::Mat& grey;
  const PredictedStar& p;
  const DetectorOptions& opts;
  cv::Rect frame, win;
  int cx = 0, cy = 0;  // predicted pixel, rounded
  cv::Point pk;        // brightest pixel (first maximum in raster order)
  double peak = 0, b = 0, sb = 0, thr = 0;
  double psf0 = 0, blur = 0;
  bool streak = false, trust_prediction = false;
};

// Fills the border ring of the window (background samples) and returns the peak value.
template <typename T>
int scanRingAndPeak(const cv::Mat& grey, const cv::Rect& win, std::vector<float>& ring,
                    cv::Point& pk) {
  ring.resize(static_cast<std::size_t>(2 * win.width + 2 * (win.height - 2)));
  float* rp = ring.data();
  int best = -1;
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
  return best;
}

// Count and background-subtracted moments of the pixels of r above the threshold.
template <typename T>
void thresholdMoments(const WindowScan& ws, const cv::Rect& r, int& area, Moments& mom) {
  // Branch-free (pixels below the threshold add zeros): whether a noise pixel is above
  // the threshold is a coin flip the branch predictor loses.
  const double thr = ws.thr, b = ws.b;
  area = 0;
  double sw = 0, sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0;
  for (int y = r.y; y < r.y + r.height; ++y) {
    const T* row = ws.grey.ptr<T>(y);
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
}

// Centre of the first centroid window. The brightest pixel of a streak can be anywhere
// along it (noise decides), so for a streak the middle is first located as the centre of the
// above-threshold pixels within a full streak length of the peak; a window centred on the
// peak would cut off up to half the streak and move the centroid by a quarter of its length.
template <typename T>
cv::Point firstCentre(const WindowScan& ws, int& area, Moments& mom) {
  // A tight prediction (tracking with a gyro) places a streak's middle better than its
  // pixels do: a faint streak breaks into fragments above the threshold, and the moments of
  // one fragment put the window on one end of the streak.
  if (ws.trust_prediction) return {ws.cx, ws.cy};
  if (!ws.streak) return ws.pk;
  const cv::Point anchor = ws.p.anchor_at_px ? cv::Point(ws.cx, ws.cy) : ws.pk;
  const int hs = static_cast<int>(std::ceil(2.5 * ws.psf0 + ws.blur));
  thresholdMoments<T>(ws, cv::Rect(anchor.x - hs, anchor.y - hs, 2 * hs + 1, 2 * hs + 1) & ws.win,
                      area, mom);
  if (mom.sw > 0)
    return {static_cast<int>(std::lround(mom.sx / mom.sw)),
            static_cast<int>(std::lround(mom.sy / mom.sw))};
  return ws.pk;
}

// Centroid in a PSF-sized window (plus half the streak) around `centre`, re-centred on the
// result: a window off the streak's middle cuts the streak and pulls the CoG towards the
// window's centre; re-centring converges to the middle (a few rounds for a streak located
// from a fragment; a tight prediction needs none).
template <typename T>
void measureRounds(const WindowScan& ws, double sat, const Centroider& main,
                   const Centroider& cog, Scratch& s, cv::Point centre, int area, Moments mom,
                   WindowResult& w) {
  const DetectorOptions& opts = ws.opts;
  const int hc = static_cast<int>(std::ceil(2.5 * ws.psf0 + 0.5 * ws.blur));
  const Centroider& c = ws.streak ? cog : main;  // a streak is not a round PSF: the CoG
                                                 // measures its middle
  const int rounds = ws.streak && !ws.trust_prediction ? 3 : 1;
  for (int round = 0; round < rounds; ++round) {
    const cv::Rect full(centre.x - hc, centre.y - hc, 2 * hc + 1, 2 * hc + 1);
    const cv::Rect cw = full & ws.win;
    uint32_t flags = 0;
    if (ws.peak >= sat) flags |= kSaturated;
    if ((full & ws.frame).area() != full.area()) flags |= kTouchesEdge;
    double psf = ws.psf0;
    if (ws.streak) {
      flags |= kElongated;  // by construction; its moments would only say so again
    } else {
      thresholdMoments<T>(ws, cw, area, mom);
      double elong = 1;
      mom.shape(elong, psf, opts.pixel_aspect);
      if (elong > opts.max_elongation) flags |= kElongated;
      if (opts.psf_sigma_px > 0) psf = opts.psf_sigma_px;
      psf = psf > 0 ? std::clamp(psf, 0.5, 5.0) : DetectorOptions::kAssumedPsfSigmaPx;
    }
    const Vec2 start = !ws.streak && mom.sw > 0 ? Vec2(mom.sx / mom.sw, mom.sy / mom.sw)
                                                : Vec2(ws.pk.x, ws.pk.y);  // as in measureBlobs
    StarPatch patch = makePatch<T>(ws.grey, cw, ws.b, ws.sb, sat, psf, start, opts, s.patch);
    patch.smear = ws.p.blur_px;
    // Variance of the ring median: pi/2 sigma^2 / n for Gaussian noise.
    patch.background_var = 0.5 * M_PI * ws.sb * ws.sb / static_cast<double>(s.ring.size());
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

}  // namespace

// One predictive window (seed 004 §4.2.3): background from the window's border ring, the
// brightest pixel inside, and the centroid in a PSF-sized window around it.
template <typename T>
void centroidWindow(const cv::Mat& grey, const PredictedStar& p, const DetectorOptions& opts,
                    double sat, const Centroider& main, const Centroider& cog, Scratch& s,
                    WindowResult& w) {
  WindowScan ws(grey, p, opts);
  if (!p.px.allFinite() || p.px.x() < -0.5 || p.px.y() < -0.5 || p.px.x() > grey.cols - 0.5 ||
      p.px.y() > grey.rows - 0.5) {
    w.reason = "outside image";
    return;
  }
  const int h = windowHalfSize(p, opts);
  ws.cx = static_cast<int>(std::lround(p.px.x()));
  ws.cy = static_cast<int>(std::lround(p.px.y()));
  ws.win = cv::Rect(ws.cx - h, ws.cy - h, 2 * h + 1, 2 * h + 1) & ws.frame;
  if (ws.win.width < 3 || ws.win.height < 3) {
    w.reason = "outside image";
    return;
  }
  ws.peak = scanRingAndPeak<T>(grey, ws.win, s.ring, ws.pk);
  robustLevelSigma(s.ring, ws.b, ws.sb);
  ws.sb = std::max({ws.sb, opts.read_noise_adu, 0.3});
  if (ws.peak - ws.b < opts.threshold_sigma * ws.sb) {
    w.reason = "below threshold";
    return;
  }
  ws.psf0 = opts.psfSigmaGuess();
  ws.blur = p.blur_px.norm();
  ws.thr = ws.b + opts.threshold_sigma * ws.sb;
  ws.streak = ws.blur > 2.0 * ws.psf0;
  // A radiation hit brighter than the star (or in place of a star not there) is refused by
  // its shape against the PSF the last full frame measured; with none measured, the gate
  // alone refuses it.
  if (opts.flag_hits && !ws.streak &&
      sharperThanPsf(peakProfile(grey, ws.pk.x, ws.pk.y, ws.b), ws.sb, s.frame_psf_x,
                     s.frame_psf_y)) {
    w.reason = "radiation hit at the window's peak";
    return;
  }
  ws.trust_prediction = ws.streak && 3.0 * largestSigma(p.cov_px) <= ws.psf0 + 0.25 * ws.blur;
  int area = 0;
  Moments mom;
  const cv::Point centre = firstCentre<T>(ws, area, mom);
  measureRounds<T>(ws, sat, main, cog, s, centre, area, mom, w);
}

template void centroidWindow<uint8_t>(const cv::Mat&, const PredictedStar&, const DetectorOptions&,
                                      double, const Centroider&, const Centroider&, Scratch&,
                                      WindowResult&);
template void centroidWindow<uint16_t>(const cv::Mat&, const PredictedStar&,
                                       const DetectorOptions&, double, const Centroider&,
                                       const Centroider&, Scratch&, WindowResult&);

}  // namespace st::detect_detail

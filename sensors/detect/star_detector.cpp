#include "sensors/detect/star_detector.hpp"

#include <algorithm>
#include <cmath>
#include <exception>

#include <mrpt/img/CImage.h>
#include <opencv2/imgproc.hpp>

#include "common/errors.hpp"
#include "sensors/detect/background.hpp"
#include "sensors/detect/blob_labeller.hpp"
#include "sensors/detect/centroider.hpp"
#include "sensors/detect/prefilter.hpp"

namespace st {
namespace {

void requireValid(const DetectorOptions& opts) {
  std::string err;
  if (!opts.isValid(&err)) throw InputError(err);
}

// One-channel 8/16-bit view of the input (a copy only for colour), or a reason.
bool greyView(const cv::Mat& in, cv::Mat& grey, std::string& reason) {
  if (in.empty()) {
    reason = "empty image";
    return false;
  }
  if (in.depth() != CV_8U && in.depth() != CV_16U) {
    reason = "unsupported image type " + cv::typeToString(in.type()) + " (want 8- or 16-bit)";
    return false;
  }
  if (in.channels() == 1) {
    grey = in;
  } else if (in.channels() == 3) {
    cv::cvtColor(in, grey, cv::COLOR_BGR2GRAY);
  } else if (in.channels() == 4) {
    cv::cvtColor(in, grey, cv::COLOR_BGRA2GRAY);
  } else {
    reason = "unsupported image type " + cv::typeToString(in.type()) + " (channels)";
    return false;
  }
  return true;
}

double saturationLevel(const cv::Mat& grey, const DetectorOptions& opts) {
  if (opts.saturation_adu > 0) return opts.saturation_adu;
  return grey.depth() == CV_8U ? 255.0 : 65535.0;
}

template <typename T>
double pix(const cv::Mat& m, int x, int y) {
  return static_cast<double>(m.ptr<T>(y)[x]);
}

// Second moments of background-subtracted pixels, fed one at a time: elongation and a PSF
// sigma estimate (the moments of a pixel-integrated Gaussian are s^2 + 1/12).
struct Moments {
  double sw = 0, sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0;
  void add(int x, int y, double w) {
    if (w <= 0) return;
    sw += w;
    sx += w * x;
    sy += w * y;
    sxx += w * x * x;
    syy += w * y * y;
    sxy += w * x * y;
  }
  Mat2 central() const {
    Mat2 m = Mat2::Zero();
    if (sw <= 0) return m;
    const double mx = sx / sw, my = sy / sw;
    m(0, 0) = sxx / sw - mx * mx;
    m(1, 1) = syy / sw - my * my;
    m(0, 1) = m(1, 0) = sxy / sw - mx * my;
    return m;
  }
  void shape(double& elongation, double& sigma) const {
    elongation = 1;
    sigma = 0;
    if (sw <= 0) return;
    const double mx = sx / sw, my = sy / sw;
    const double a = sxx / sw - mx * mx, b = syy / sw - my * my, c = sxy / sw - mx * my;
    const double tr = 0.5 * (a + b);
    const double dd = std::sqrt(std::max(0.0, 0.25 * (a - b) * (a - b) + c * c));
    const double l1 = tr + dd, l2 = std::max(tr - dd, 1.0 / 12.0);
    elongation = std::sqrt(l1 / l2);
    sigma = std::sqrt(std::max(tr - 1.0 / 12.0, 0.0));
  }
};

// Largest of n pixel values: a plain max reduction, vectorised (unsigned integer max needs
// SSE4.1 or AVX2, hence the clones); the search windows of fast-moving stars are ~1000 pixels.
#if defined(__GNUC__) && defined(__x86_64__)
#define ST_PIXEL_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define ST_PIXEL_CLONES
#endif
ST_PIXEL_CLONES int maxOf(const uint8_t* p, int n) {
  uint8_t m = 0;
  for (int i = 0; i < n; ++i) m = std::max(m, p[i]);
  return m;
}
ST_PIXEL_CLONES int maxOf(const uint16_t* p, int n) {
  uint16_t m = 0;
  for (int i = 0; i < n; ++i) m = std::max(m, p[i]);
  return m;
}

// A patch over `r` whose values live in a per-thread buffer: no allocation per star once the
// buffer has grown to the largest window (valid until the next call on this thread).
template <typename T>
StarPatch makePatch(const cv::Mat& grey, const cv::Rect& r, double bg, double sigma_bg,
                    double sat, double psf, const Vec2& guess, const DetectorOptions& opts) {
  thread_local std::vector<float> buf;
  buf.resize(static_cast<std::size_t>(r.area()));
  float* out = buf.data();
  for (int y = r.y; y < r.y + r.height; ++y) {
    const T* row = grey.ptr<T>(y);
    for (int x = r.x; x < r.x + r.width; ++x) *out++ = static_cast<float>(row[x]);
  }
  StarPatch p;
  p.values = cv::Mat1f(r.height, r.width, buf.data());  // a header only
  p.origin = r.tl();
  p.background = bg;
  p.sigma_bg = sigma_bg;
  p.gain = opts.gain_e_per_adu;
  p.saturation = sat;
  p.psf_sigma = psf;
  p.guess = guess;
  p.reject_spikes = opts.reject_spikes;
  return p;
}

// One instance of each centroider for the whole program (they are stateless).
const Centroider& centroiderNamed(const std::string& name) {
  static const std::vector<std::unique_ptr<Centroider>> all = [] {
    std::vector<std::unique_ptr<Centroider>> v;
    for (const std::string& n : Centroider::names()) v.push_back(Centroider::create(n));
    return v;
  }();
  for (const auto& c : all)
    if (c->name() == name) return *c;
  throw InputError("unknown centroider '" + name + "'");
}

// The configured centroider, with the plain CoG as the fallback when it fails.
bool measure(const Centroider& main, const Centroider& fallback, const StarPatch& p,
             Centroid& c, std::string* reason) {
  if (main.centroid(p, c, reason)) return true;
  return &main != &fallback && fallback.centroid(p, c, reason);
}

struct Candidate {
  int blob;
  double sum;
};

template <typename T>
DetectionResult measureBlobs(const cv::Mat& grey, const BackgroundModel& bg,
                             const BlobLabeller& lab, const DetectorOptions& opts,
                             DetectionResult res) {
  const double sat = saturationLevel(grey, opts);
  const std::vector<Blob>& blobs = lab.blobs();
  // Brightness of each blob above its local background, for the brightest-first order.
  thread_local std::vector<Candidate> cands;
  cands.clear();
  for (std::size_t i = 0; i < blobs.size(); ++i) {
    const Blob& bl = blobs[i];
    if (bl.area < opts.min_area || bl.area > opts.max_area) {
      ++res.rejected;
      continue;
    }
    const cv::Rect box = bl.box();
    const double b = bg.levelAt(box.x + 0.5 * box.width, box.y + 0.5 * box.height);
    cands.push_back({static_cast<int>(i), bl.sum_raw - bl.area * b});
  }
  std::sort(cands.begin(), cands.end(),
            [](const Candidate& a, const Candidate& b) { return a.sum > b.sum; });

  const Centroider& main = centroiderNamed(opts.centroider);
  const Centroider& cog = centroiderNamed("cog");
  const cv::Rect frame(0, 0, grey.cols, grey.rows);
  const double min_sep2 = opts.min_separation_px * opts.min_separation_px;
  res.stars.reserve(static_cast<std::size_t>(std::min<std::size_t>(
      static_cast<std::size_t>(opts.max_stars), cands.size())));
  for (const Candidate& cand : cands) {
    if (static_cast<int>(res.stars.size()) >= opts.max_stars) break;
    const Blob& c = blobs[static_cast<std::size_t>(cand.blob)];
    const cv::Rect box = c.box();
    const double b = bg.levelAt(c.peak.x, c.peak.y), sb = bg.sigmaAt(c.peak.x, c.peak.y);
    uint32_t flags = 0;
    if (box.x == 0 || box.y == 0 || box.x + box.width == grey.cols ||
        box.y + box.height == grey.rows)
      flags |= kTouchesEdge;
    if (c.peak_raw >= sat) flags |= kSaturated;
    Moments mom;
    lab.forEachPixel(grey, c, [&](int x, int y, double v) { mom.add(x, y, v - b); });
    double elong = 1, psf = 0;
    mom.shape(elong, psf);
    if (elong > opts.max_elongation) flags |= kElongated;
    // Hot pixel: nearly all the light of the 3x3 around the peak in the peak itself.
    const cv::Rect r3 = cv::Rect(c.peak.x - 1, c.peak.y - 1, 3, 3) & frame;
    double s3 = 0;
    for (int y = r3.y; y < r3.y + r3.height; ++y)
      for (int x = r3.x; x < r3.x + r3.width; ++x) s3 += std::max(pix<T>(grey, x, y) - b, 0.0);
    if (s3 > 0 && (c.peak_raw - b) / s3 > opts.hot_pixel_fraction && !(flags & kSaturated))
      flags |= kHotPixel;
    if (flags & opts.reject_flags) {
      ++res.rejected;
      continue;
    }
    if (opts.psf_sigma_px > 0) psf = opts.psf_sigma_px;
    psf = psf > 0 ? std::clamp(psf, 0.5, 5.0) : DetectorOptions::kAssumedPsfSigmaPx;
    // Window: the blob's box plus a margin, and at least +-2.5 PSF sigma around the peak.
    const int h = static_cast<int>(std::ceil(2.5 * psf));
    cv::Rect win(box.x - opts.window_margin_px, box.y - opts.window_margin_px,
                 box.width + 2 * opts.window_margin_px, box.height + 2 * opts.window_margin_px);
    win |= cv::Rect(c.peak.x - h, c.peak.y - h, 2 * h + 1, 2 * h + 1);
    win &= frame;
    // First position: the blob's centre of light (a model fit starts closer than from the
    // window's centre of gravity, which the noise of every window pixel moves).
    const Vec2 start = mom.sw > 0 ? Vec2(mom.sx / mom.sw, mom.sy / mom.sw) : Vec2(c.peak.x, c.peak.y);
    StarPatch patch = makePatch<T>(grey, win, b, sb, sat, psf, start, opts);
    // Median of `background_samples` pixels per tile (16x that globally): pi/2 sigma^2 / n.
    patch.background_var = 0.5 * M_PI * sb * sb /
                           (opts.background_samples * (opts.background_tile_px > 0 ? 1.0 : 16.0));
    Centroid star;
    if (!measure(main, cog, patch, star, nullptr)) {
      ++res.rejected;
      continue;
    }
    star.area = c.area;
    star.flags = flags;
    star.shape = mom.central();
    bool dup = false;
    for (const Centroid& o : res.stars)
      if ((o.px - star.px).squaredNorm() < min_sep2) dup = true;
    if (dup) {
      ++res.duplicates;
      continue;
    }
    res.stars.push_back(star);
  }
  std::stable_sort(res.stars.begin(), res.stars.end(),
                   [](const Centroid& a, const Centroid& b) { return a.flux > b.flux; });
  if (res.stars.empty()) res.reason = "no blob passed the filters";
  return res;
}

// Square root of the largest eigenvalue of the symmetric part of a 2x2 covariance.
double largestSigma(const Mat2& cov) {
  const double a = cov(0, 0), d = cov(1, 1), c = 0.5 * (cov(0, 1) + cov(1, 0));
  const double lmax = 0.5 * (a + d) + std::sqrt(0.25 * (a - d) * (a - d) + c * c);
  return std::sqrt(std::max(lmax, 0.0));
}

// One predictive window (seed 004 §4.2.3): background from the window's border ring, the
// brightest pixel inside, and the centroid in a PSF-sized window around it.
template <typename T>
void centroidWindow(const cv::Mat& grey, const PredictedStar& p, const DetectorOptions& opts,
                    double sat, const Centroider& main, const Centroider& cog, WindowResult& w) {
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
  thread_local std::vector<float> ring;
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
    StarPatch patch = makePatch<T>(grey, cw, b, sb, sat, psf, start, opts);
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

}  // namespace

DetectionResult detectStars(const cv::Mat& image, const DetectorOptions& opts) {
  requireValid(opts);
  DetectionResult res;
  cv::Mat grey;
  if (!greyView(image, grey, res.reason)) return res;
  if (!opts.dark_frame.empty()) {
    if (opts.dark_frame.size() != grey.size() || opts.dark_frame.type() != grey.type()) {
      res.reason = "dark frame size/type differs from the image";
      return res;
    }
    cv::Mat sub;
    cv::subtract(grey, opts.dark_frame, sub);  // saturating: never below 0
    grey = sub;
  }
  const double sat = saturationLevel(grey, opts);
  const BackgroundModel bg = estimateBackground(grey, opts.background_tile_px,
                                                opts.background_samples, opts.read_noise_adu);
  res.background = bg.level;
  res.noise_sigma = bg.sigma;
  if (bg.level >= sat) {
    res.reason = "image saturated (background at the saturation level)";
    return res;
  }

  // Threshold at k sigma above the (tiled) background (seed 004 §4.1), blobs 8-connected.
  thread_local BlobLabeller lab;
  const double k = opts.threshold_sigma;
  if (opts.prefilter == "none") {
    // Sparse: only the pixels above the threshold are ever visited after the compare.
    thread_local std::vector<double> thr;
    if (bg.tile > 0) {
      thr.resize(bg.tile_level.size());
      for (std::size_t i = 0; i < thr.size(); ++i) thr[i] = bg.tile_level[i] + k * bg.tile_sigma[i];
    } else {
      thr.assign(1, bg.level + k * bg.sigma);
    }
    lab.labelThreshold(grey, bg.tile, bg.tile > 0 ? bg.tiles_x : 1, thr);
  } else {
    // The pre-filters count candidates in 5x5 neighbourhoods: they need the mask.
    cv::Mat mask(grey.size(), CV_8U);
    if (bg.tile > 0) {
      for (int ty = 0; ty < bg.tiles_y; ++ty)
        for (int tx = 0; tx < bg.tiles_x; ++tx) {
          const cv::Rect r(tx * bg.tile, ty * bg.tile,
                           std::min(bg.tile, grey.cols - tx * bg.tile),
                           std::min(bg.tile, grey.rows - ty * bg.tile));
          const std::size_t i = static_cast<std::size_t>(ty * bg.tiles_x + tx);
          cv::compare(grey(r), bg.tile_level[i] + k * bg.tile_sigma[i], mask(r), cv::CMP_GT);
        }
    } else {
      cv::compare(grey, bg.level + k * bg.sigma, mask, cv::CMP_GT);
    }
    applyPrefilter(mask, opts.prefilter, opts.prefilter_min_count);
    lab.labelMask(mask, grey);
  }
  res.blobs_found = static_cast<int>(lab.blobs().size());
  if (lab.blobs().empty()) {
    double lo = 0, hi = 0;
    cv::minMaxLoc(grey, &lo, &hi);
    res.reason = lo == hi ? "blank image (constant value " + std::to_string(lo) + ")"
                          : "no pixel above the threshold";
    return res;
  }
  return grey.depth() == CV_8U ? measureBlobs<uint8_t>(grey, bg, lab, opts, std::move(res))
                               : measureBlobs<uint16_t>(grey, bg, lab, opts, std::move(res));
}

int windowHalfSize(const PredictedStar& p, const DetectorOptions& opts) {
  const double sd = largestSigma(p.cov_px);
  const double psf = opts.psfSigmaGuess();
  const double h = opts.window_sigmas * sd + 3.0 * psf + 0.5 * p.blur_px.norm();
  if (!std::isfinite(h)) return opts.max_window_half_px;
  return std::clamp(static_cast<int>(std::ceil(h)), 2, opts.max_window_half_px);
}

std::vector<WindowResult> centroidWindows(const cv::Mat& image,
                                          const std::vector<PredictedStar>& predicted,
                                          const DetectorOptions& opts) {
  requireValid(opts);
  std::vector<WindowResult> out(predicted.size());
  cv::Mat grey;
  std::string why;
  if (!greyView(image, grey, why)) {
    for (auto& w : out) w.reason = why;
    return out;
  }
  const double sat = saturationLevel(grey, opts);
  const Centroider& main = centroiderNamed(opts.centroider);
  const Centroider& cog = centroiderNamed("cog");
  for (std::size_t i = 0; i < predicted.size(); ++i) {
    if (grey.depth() == CV_8U)
      centroidWindow<uint8_t>(grey, predicted[i], opts, sat, main, cog, out[i]);
    else
      centroidWindow<uint16_t>(grey, predicted[i], opts, sat, main, cog, out[i]);
  }
  return out;
}

DetectionResult detectStars(const mrpt::img::CImage& image, const DetectorOptions& opts) {
  requireValid(opts);
  try {
    return detectStars(image.asCvMatRef(), opts);
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    DetectionResult r;
    r.reason = std::string("cannot read image: ") + e.what();
    return r;
  }
}

std::vector<WindowResult> centroidWindows(const mrpt::img::CImage& image,
                                          const std::vector<PredictedStar>& predicted,
                                          const DetectorOptions& opts) {
  requireValid(opts);
  try {
    return centroidWindows(image.asCvMatRef(), predicted, opts);
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    std::vector<WindowResult> out(predicted.size());
    for (auto& w : out) w.reason = std::string("cannot read image: ") + e.what();
    return out;
  }
}

}  // namespace st

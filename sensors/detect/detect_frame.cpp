// Full-frame detection (seed 004 §4.1): background, threshold, blobs, and a centroid per blob
// with the detector's centroider; every buffer is the detector's scratch.
#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

#include "common/check.hpp"
#include "sensors/detect/detect_internal.hpp"
#include "sensors/detect/prefilter.hpp"
#include "sensors/detect/radiation_hits.hpp"

namespace st::detect_detail {
namespace {

// [background sigmas] the least peak of a blob judged as a hot-pixel cluster (see blobFlags).
constexpr double kHotClusterSigma = 100;
// [background sigmas] the least peak whose ties are read as a clipped top (see blobFlags).
constexpr double kFlatTopSigma = 20;

// Level of the one-pixel border of `r` (inside the frame): the background right around a
// blob. Where the background curves (a glow's core) or steps (a skyline), the tiles'
// interpolation misses it by many sigmas; a star's surroundings are its background.
template <typename T>
double borderLevel(const cv::Mat& grey, const cv::Rect& r, std::vector<float>& buf) {
  buf.clear();
  for (int x = r.x; x < r.x + r.width; ++x) {
    buf.push_back(static_cast<float>(pix<T>(grey, x, r.y)));
    buf.push_back(static_cast<float>(pix<T>(grey, x, r.y + r.height - 1)));
  }
  for (int y = r.y + 1; y + 1 < r.y + r.height; ++y) {
    buf.push_back(static_cast<float>(pix<T>(grey, r.x, y)));
    buf.push_back(static_cast<float>(pix<T>(grey, r.x + r.width - 1, y)));
  }
  double level = 0, sigma = 0;
  robustLevelSigma(buf, level, sigma);
  return level;
}

// At most this many rejected blobs are listed (a picture of a failed frame needs no more).
constexpr std::size_t kMaxListedRejected = 2000;

void listRejected(DetectionResult& res, const Blob& bl, uint32_t flags) {
  ++res.rejected;
  if (res.rejected_blobs.size() < kMaxListedRejected)
    res.rejected_blobs.push_back({Vec2(bl.peak.x, bl.peak.y), bl.area, flags});
}

// Blobs of an accepted area, ranked by the significance of their peak above the local
// background, in local noise sigmas (most significant first). Not by total flux: a lit
// foreground, a glow or a skyline's edge holds far more light than any star, in a blob that
// is only a few sigma above its surroundings; a star is a sharp peak.
void rankCandidates(const DetectorOptions& opts, Scratch& s, DetectionResult& res) {
  const BackgroundModel& bg = s.background;
  const std::vector<Blob>& blobs = s.labeller.blobs();
  std::vector<Candidate>& cands = s.candidates;
  cands.clear();
  for (std::size_t i = 0; i < blobs.size(); ++i) {
    const Blob& bl = blobs[i];
    if (bl.area < opts.min_area || bl.area > opts.max_area) {
      listRejected(res, bl, 0);
      continue;
    }
    const double x = bl.peak.x, y = bl.peak.y;
    cands.push_back({static_cast<int>(i), (bl.peak_raw - bg.levelAt(x, y)) / bg.sigmaAt(x, y)});
  }
  std::sort(cands.begin(), cands.end(),
            [](const Candidate& a, const Candidate& b) { return a.sum > b.sum; });
}

// Mean above `b` of the pixels just outside the blob's box (its ring), 0 when none.
template <typename T>
double ringMean(const cv::Mat& grey, const cv::Rect& box, double b) {
  const cv::Rect frame(0, 0, grey.cols, grey.rows);
  const cv::Rect outer = cv::Rect(box.x - 1, box.y - 1, box.width + 2, box.height + 2) & frame;
  double sum = 0;
  int n = 0;
  for (int y = outer.y; y < outer.y + outer.height; ++y)
    for (int x = outer.x; x < outer.x + outer.width; ++x)
      if (!box.contains({x, y})) {
        sum += pix<T>(grey, x, y) - b;
        ++n;
      }
  return n > 0 ? sum / n : 0;
}

// Flags of a blob (edge, saturation, elongation, hot pixel, extended), its moments above the
// background b and the PSF sigma they give (0 when they give none).
template <typename T>
uint32_t blobFlags(const cv::Mat& grey, const Blob& c, const BlobLabeller& lab, double b,
                   double sb, double sat, double top, const DetectorOptions& opts,
                   double psf_lim, Moments& mom, double& psf, bool& flat_top,
                   int& wing_px, int& clipped_px) {
  const cv::Rect frame(0, 0, grey.cols, grey.rows);
  const cv::Rect box = c.box();
  uint32_t flags = 0;
  if (box.x == 0 || box.y == 0 || box.x + box.width == grey.cols ||
      box.y + box.height == grey.rows)
    flags |= kTouchesEdge;
  if (c.peak_raw >= sat) flags |= kSaturated;
  int n_sat = 0, n_top = 0, n_low = 0;
  const double half = 0.5 * (c.peak_raw + b);
  lab.forEachPixel(grey, c, [&](int x, int y, double v) {
    mom.add(x, y, v - b);
    n_sat += v >= sat;
    n_top += v >= c.peak_raw;
    n_low += v < half;
  });
  // Two or more pixels at the frame's highest value `top`, far above the noise: a clipped
  // top, also where the clip level is not known (12-bit data in a 16-bit word without a
  // shift clip at 4095). Ties at lower values (a lit foreground's mottling) say nothing.
  flat_top = n_top >= 2 && c.peak_raw >= top && c.peak_raw - b > kFlatTopSigma * sb;
  wing_px = n_low;
  clipped_px = std::max(n_sat, n_top);
  double elong = 1;
  psf = 0;
  mom.shape(elong, psf, opts.pixel_aspect);
  if (elong > opts.max_elongation) flags |= kElongated;
  // Extended: wider across its narrow axis than a PSF, beyond what a saturated core (a flat
  // disc of n_sat pixels: variance n_sat / (4 pi) per axis) explains.
  const double minor_var = mom.minorVariance() - 1.0 / 12.0;
  if (minor_var > psf_lim * psf_lim + 1.5 * n_sat / (4 * M_PI)) flags |= kExtended;
  // A clipped top with more pixels below half of it than a star's wings hold: a PSF of sigma
  // s puts 2 pi s^2 ln(P / 2T) pixels between the threshold T and half the peak P; psf_lim
  // is already twice the frame's PSF.
  const double thr = opts.threshold_sigma * sb;
  if (flat_top && n_low > 2 * M_PI * psf_lim * psf_lim *
                              std::log(std::max((c.peak_raw - b) / (2 * thr), 2.0)) + 10)
    flags |= kExtended;
  // A cluster of hot pixels, or a lamp or a lit window in the foreground: bright
  // (> kHotClusterSigma), small or flat-topped, no pixel of the blob below half its peak and
  // nothing just around it. The sharpest star (PSF sigma 0.5 px, centred on a pixel corner:
  // four equal pixels) puts 3.2 % of its peak on the ring around its box, a clipped one more;
  // the ring's noise is below 0.3 % of such a peak.
  if ((c.area <= 9 || flat_top) && n_low == 0 && c.peak_raw - b > kHotClusterSigma * sb &&
      ringMean<T>(grey, box, b) < 0.015 * (c.peak_raw - b))
    flags |= kHotPixel;
  if (flags & kSaturated) return flags;
  // Hot pixel: nearly all the light of the 3x3 around the peak in the peak itself.
  const cv::Rect r3 = cv::Rect(c.peak.x - 1, c.peak.y - 1, 3, 3) & frame;
  double s3 = 0;
  for (int y = r3.y; y < r3.y + r3.height; ++y)
    for (int x = r3.x; x < r3.x + r3.width; ++x) s3 += std::max(pix<T>(grey, x, y) - b, 0.0);
  if (s3 > 0 && (c.peak_raw - b) / s3 > opts.hot_pixel_fraction) flags |= kHotPixel;
  return flags;
}

// Centroid of one blob, measured in its box plus a margin; false when the centroiders fail.
template <typename T>
bool centroidBlob(const cv::Mat& grey, const Blob& c, const Moments& mom, double b, double sb,
                  double sat, double psf, const DetectorOptions& opts, const Centroider& main,
                  const Centroider& cog, Scratch& s, Centroid& star) {
  const cv::Rect frame(0, 0, grey.cols, grey.rows);
  const cv::Rect box = c.box();
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
  StarPatch patch = makePatch<T>(grey, win, b, sb, sat, psf, start, opts, s.patch);
  // Median of `background_samples` pixels per tile (16x that globally): pi/2 sigma^2 / n.
  patch.background_var = 0.5 * M_PI * sb * sb /
                         (opts.background_samples * (opts.background_tile_px > 0 ? 1.0 : 16.0));
  return measure(main, cog, patch, star, nullptr);
}

// [px] The widest PSF sigma a star of this frame may have: twice the median moment sigma of
// the most significant unclipped blobs (the moments of a star above the threshold understate
// its sigma), plus half a pixel; opts.max_psf_sigma_px when fewer than 5 tell. Clutter
// (lamps, edges, glows) is wider or clipped, and rarely the majority of the most significant.
template <typename T>
double psfLimit(const cv::Mat& grey, const DetectorOptions& opts, Scratch& s, double sat) {
  const BackgroundModel& bg = s.background;
  const std::vector<Blob>& blobs = s.labeller.blobs();
  thread_local std::vector<double> sig;
  sig.clear();
  for (std::size_t i = 0; i < s.candidates.size() && i < 30; ++i) {
    const Blob& c = blobs[static_cast<std::size_t>(s.candidates[i].blob)];
    if (c.area < 3 || c.peak_raw >= sat) continue;
    const double b = bg.levelAt(c.peak.x, c.peak.y);
    Moments mom;
    int n_top = 0;
    s.labeller.forEachPixel(grey, c, [&](int x, int y, double v) {
      mom.add(x, y, v - b);
      n_top += v >= c.peak_raw;
    });
    double elong = 1, psf = 0;
    mom.shape(elong, psf, opts.pixel_aspect);
    if (n_top < 2 && elong <= opts.max_elongation && psf > 0) sig.push_back(psf);
  }
  if (sig.size() < 5) return opts.max_psf_sigma_px;
  const auto mid = sig.begin() + static_cast<std::ptrdiff_t>(sig.size() / 2);
  std::nth_element(sig.begin(), mid, sig.end());
  return std::min(opts.max_psf_sigma_px, 2 * *mid + 0.5);
}

// The frame's PSF along x and y (radiation_hits.hpp): the widest tight cluster of the three-pixel
// widths of its most significant unclipped blobs.
void framePsf(const cv::Mat& grey, Scratch& s, double sat, DetectionResult& res) {
  const BackgroundModel& bg = s.background;
  const std::vector<Blob>& blobs = s.labeller.blobs();
  thread_local std::vector<AxisWidth> widths;
  widths.clear();
  for (std::size_t i = 0; i < s.candidates.size() && static_cast<int>(widths.size()) < kMaxPsfBlobs; ++i) {
    const Blob& c = blobs[static_cast<std::size_t>(s.candidates[i].blob)];
    const double b = bg.levelAt(c.peak.x, c.peak.y);
    if (c.peak_raw >= sat || c.peak_raw - b < kPsfSettingPeakSigma * bg.sigmaAt(c.peak.x, c.peak.y))
      continue;
    // A significant blob with no light beside its peak along an axis is no star (a star's
    // neighbours hold > 5 % of its peak): it does not set the PSF; nor does a flat top.
    const AxisWidth w = profileWidth(grey, c.peak.x, c.peak.y, b);
    if (w.x > 0 && w.y > 0 && w.x < 10 && w.y < 10) widths.push_back(w);
  }
  const AxisWidth psf = frameWidth(widths);
  res.psf_width_x = s.frame_psf_x = psf.x;
  res.psf_width_y = s.frame_psf_y = psf.y;
}

// What a star of this frame looks like, from the median m of flux over peak pixel of its
// well-measured unclipped stars (m = 2 pi s^2 for a Gaussian PSF of sigma s):
//  - flux over peak: an undersampled PSF (the tetra3 frames: s ~ 0.7 px) puts from 1/4 to
//    all of its central light in one pixel; those frames' bright stars reach 2.6 m. A flat
//    6x4 px lamp against s = 1 px: 24 / 6.3 = 3.8 m.
//  - wing pixels, between the threshold T and half the peak P: m ln(P / 2T) for a Gaussian,
//    whatever the true peak of a clipped one (then P is the clip). A real PSF's halo puts
//    more there: the tetra3 frames' saturated stars up to 4.4x; a lamp in a lit foreground's
//    light 5-10x.
//  - core pixels, at or above half the peak, of an unclipped one: m ln 2 for a Gaussian; a
//    plateau (a lamp just below the clip, a lit window) has its whole area there.
//  - clipped pixels: m ln(P / C) for a star of true peak P above the clip C.
constexpr double kDiffuseMinPeakSigma = 10;  // [noise sigmas] a peak that sets m
constexpr double kRatioClearly = 3.0;        // [m] flux over peak of no star
constexpr double kRatioWide = 1.6;           // [m] ... of a wide one, if its wings say so too
constexpr double kWingsWide = 3.0;           // [x Gaussian] wings of an unclipped wide one
constexpr double kWingsClipped = 6.0;        // [x Gaussian] wings of no clipped star
constexpr double kCoreFactor = 4.0;          // [x Gaussian] core of no unclipped star
constexpr double kMaxClipLog = 10;  // ln P/C of the brightest star: 22,000x, 11 mag over the clip
constexpr double kMarginPx = 10;    // [px] a small disc's pixel sampling

// kDiffuse on the stars that do not look like this frame's stars (above); none when fewer
// than 5 set m.
void flagDiffuse(std::vector<Centroid>& stars, const std::vector<PeakShape>& shape) {
  thread_local std::vector<double> ratio;
  ratio.clear();
  for (std::size_t i = 0; i < stars.size(); ++i)
    if (shape[i].sets_median) ratio.push_back(stars[i].flux / stars[i].peak);
  if (ratio.size() < 5) return;
  const auto mid = ratio.begin() + static_cast<std::ptrdiff_t>(ratio.size() / 2);
  std::nth_element(ratio.begin(), mid, ratio.end());
  const double m = *mid;
  const double max_core_px = kCoreFactor * m * std::log(2.0) + kMarginPx;
  for (std::size_t i = 0; i < stars.size(); ++i) {
    const PeakShape& p = shape[i];
    const double gaussian_wings = m * p.wing_log;
    const double r = stars[i].flux / stars[i].peak;
    const bool diffuse =
        p.unclipped ? r > kRatioClearly * m ||
                          (r > kRatioWide * m && p.wing_px > kWingsWide * gaussian_wings + kMarginPx) ||
                          stars[i].area - p.wing_px > max_core_px
                    : p.wing_px > kWingsClipped * gaussian_wings + kMarginPx ||
                          p.clipped_px > kMaxClipLog * m + kMarginPx;
    if (diffuse) stars[i].flags |= kDiffuse;
  }
}

// Brightest first, ties in candidate order; the diffuse ones, and when most stars are round
// the elongated ones, after the others (a lamp, a trail, a branch's lit edge, a glow's rim:
// their flux says little about a star's magnitude, and the brightest few form the patterns of
// lost-in-space). In a slew most are streaks and their order is by flux alone. An insertion
// sort: stable without std::stable_sort's temporary buffer (an allocation per frame).
void sortBrightestFirst(std::vector<Centroid>& stars) {
  std::size_t elongated = 0;
  for (const Centroid& c : stars) elongated += (c.flags & kElongated) != 0;
  const uint32_t demoted = kDiffuse | (2 * elongated < stars.size() ? kElongated : 0u);
  // Radiation hits after everything else: the stars' prefix is what lost-in-space takes.
  const auto rank = [demoted](const Centroid& c) {
    return (c.flags & kRadiationHit) ? 2 : (c.flags & demoted) ? 1 : 0;
  };
  const auto before = [&rank](const Centroid& a, const Centroid& b) {
    const int ra = rank(a), rb = rank(b);
    return ra != rb ? ra < rb : a.flux > b.flux;
  };
  for (std::size_t i = 1; i < stars.size(); ++i)
    for (std::size_t j = i; j > 0 && before(stars[j], stars[j - 1]); --j)
      std::swap(stars[j], stars[j - 1]);
}

template <typename T>
void measureBlobs(const cv::Mat& grey, const DetectorOptions& opts, const Centroider& main,
                  const Centroider& cog, Scratch& s, DetectionResult& res) {
  const BackgroundModel& bg = s.background;
  const BlobLabeller& lab = s.labeller;
  const double sat = saturationLevel(grey, opts, bg.step);
  const std::vector<Blob>& blobs = lab.blobs();
  rankCandidates(opts, s, res);
  const std::vector<Candidate>& cands = s.candidates;
  const double psf_lim = psfLimit<T>(grey, opts, s, sat);
  if (opts.flag_hits) framePsf(grey, s, sat, res);
  double top = 0;  // the frame's highest value above the threshold: the clip, if any clipped
  for (const Blob& c : blobs) top = std::max(top, c.peak_raw);
  top = std::min(top, sat);
  const double min_sep2 = opts.min_separation_px * opts.min_separation_px;
  s.peak_shapes.clear();
  res.stars.reserve(static_cast<std::size_t>(std::min<std::size_t>(
      static_cast<std::size_t>(opts.max_stars), cands.size())));
  for (const Candidate& cand : cands) {
    if (static_cast<int>(res.stars.size()) >= opts.max_stars) break;
    const Blob& c = blobs[static_cast<std::size_t>(cand.blob)];
    double b = bg.levelAt(c.peak.x, c.peak.y);
    const double sb = bg.sigmaAt(c.peak.x, c.peak.y);
    if (bg.gradient) {
      // A structured background: a star must stand out of its own surroundings, a ring a
      // PSF's reach outside its blob.
      const int m = static_cast<int>(std::ceil(2.5 * opts.psfSigmaGuess())) + 1;
      const cv::Rect ring = cv::Rect(c.x0 - m, c.y0 - m, c.x1 - c.x0 + 1 + 2 * m,
                                     c.y1 - c.y0 + 1 + 2 * m) & cv::Rect(0, 0, grey.cols, grey.rows);
      b = borderLevel<T>(grey, ring, s.ring);
      if (c.peak_raw - b < opts.threshold_sigma * sb) {
        listRejected(res, c, 0);
        continue;
      }
    }
    Moments mom;
    double psf = 0;
    bool flat_top = false;
    int wing_px = 0, clipped_px = 0;
    uint32_t flags = blobFlags<T>(grey, c, lab, b, sb, sat, top, opts, psf_lim, mom, psf,
                                  flat_top, wing_px, clipped_px);
    Centroid star;
    if ((flags & opts.reject_flags) ||
        !centroidBlob<T>(grey, c, mom, b, sb, sat, psf, opts, main, cog, s, star)) {
      listRejected(res, c, flags & opts.reject_flags);
      continue;
    }
    // Light spread far beyond a PSF around a low peak (a foreground's edge, a glow's rim): the
    // fitted flux over the peak is 2 pi sigma^2 for a star of PSF sigma. A clipped top lowers
    // the peak of a bright star: those are judged by their shape alone.
    if (!(flags & kSaturated) && !flat_top && star.peak > 0 &&
        star.flux > 2 * M_PI * psf_lim * psf_lim * star.peak) {
      flags |= kExtended;
      if (flags & opts.reject_flags) {
        listRejected(res, c, flags & opts.reject_flags);
        continue;
      }
    }
    // Sharper than the frame's stars along x or y even with the noise's benefit of the doubt.
    if (opts.flag_hits &&
        sharperThanPsf(peakProfile(grey, c.peak.x, c.peak.y, b), sb, res.psf_width_x,
                       res.psf_width_y)) {
      flags |= kRadiationHit;
      ++res.hits;
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
    const bool unclipped = !(flags & kSaturated) && !flat_top && star.peak > 0;
    const double wing_log =
        std::log(std::max((c.peak_raw - b) / (2 * opts.threshold_sigma * sb), 2.0));
    s.peak_shapes.push_back({unclipped, unclipped && star.peak > kDiffuseMinPeakSigma * sb,
                             wing_px, clipped_px, wing_log});
  }
  flagDiffuse(res.stars, s.peak_shapes);
  sortBrightestFirst(res.stars);
  if (res.stars.empty()) res.reason = "no blob passed the filters";
}

}  // namespace

void detectFrame(const cv::Mat& grey, const DetectorOptions& opts, const Centroider& main,
                 const Centroider& cog, Scratch& s, DetectionResult& res) {
  // StarDetector::detect hands over greyView's output only.
  ST_ASSERT(grey.channels() == 1 && (grey.depth() == CV_8U || grey.depth() == CV_16U));
  res.stars.clear();  // keeps its capacity
  res.reason.clear();
  res.background = res.noise_sigma = 0;
  res.blobs_found = res.rejected = res.duplicates = res.hits = 0;
  res.psf_width_x = res.psf_width_y = 0;
  res.rejected_blobs.clear();
  estimateBackground(grey, opts.background_tile_px, opts.background_samples,
                     opts.read_noise_adu, s.background);
  const BackgroundModel& bg = s.background;
  const double sat = saturationLevel(grey, opts, bg.step);
  res.background = bg.level;
  res.noise_sigma = bg.sigma;
  if (bg.level >= sat) {
    res.reason = "image saturated (background at the saturation level)";
    return;
  }

  // Threshold at k sigma above the (tiled) background (seed 004 §4.1), blobs 8-connected.
  BlobLabeller& lab = s.labeller;
  const double k = opts.threshold_sigma;
  // A gradient (or an edge) that even the finer tiles of a graded background step across:
  // the threshold follows the interpolated level pixel by pixel; else it is constant per tile
  // (a sparse compare: vignetting and mild sky glow stay on the fast path).
  const bool follow = bg.gradient && hasGradient(bg, kMaxTileChangeSigma);
  if (opts.prefilter == "none" && !follow) {
    // Sparse: only the pixels above the threshold are ever visited after the compare.
    std::vector<double>& thr = s.thresholds;
    if (bg.tile > 0) {
      thr.resize(bg.tile_level.size());
      for (std::size_t i = 0; i < thr.size(); ++i) thr[i] = bg.tile_level[i] + k * bg.tile_sigma[i];
    } else {
      thr.assign(1, bg.level + k * bg.sigma);
    }
    lab.labelThreshold(grey, bg.tile, bg.tile > 0 ? bg.tiles_x : 1, thr);
  } else {
    // The pre-filters count candidates in 5x5 neighbourhoods: they need the mask.
    cv::Mat& mask = s.mask;
    mask.create(grey.size(), CV_8U);
    if (follow) {
      thresholdMask(grey, bg, k, s.threshold_map, mask);
    } else if (bg.tile > 0) {
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
    return;
  }
  if (grey.depth() == CV_8U)
    measureBlobs<uint8_t>(grey, opts, main, cog, s, res);
  else
    measureBlobs<uint16_t>(grey, opts, main, cog, s, res);
}

}  // namespace st::detect_detail

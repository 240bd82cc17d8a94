// Full-frame detection (seed 004 §4.1): background, threshold, blobs, and a centroid per blob
// with the detector's centroider; every buffer is the detector's scratch.
#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

#include "common/check.hpp"
#include "sensors/detect/detect_internal.hpp"
#include "sensors/detect/prefilter.hpp"

namespace st::detect_detail {
namespace {

// Blobs of an accepted area, ranked by their brightness above the local background
// (brightest first).
void rankCandidates(const DetectorOptions& opts, Scratch& s, DetectionResult& res) {
  const BackgroundModel& bg = s.background;
  const std::vector<Blob>& blobs = s.labeller.blobs();
  std::vector<Candidate>& cands = s.candidates;
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
}

// Flags of a blob (edge, saturation, elongation, hot pixel), its moments above the
// background b and the PSF sigma they give (0 when they give none).
template <typename T>
uint32_t blobFlags(const cv::Mat& grey, const Blob& c, const BlobLabeller& lab, double b,
                   double sat, const DetectorOptions& opts, Moments& mom, double& psf) {
  const cv::Rect frame(0, 0, grey.cols, grey.rows);
  const cv::Rect box = c.box();
  uint32_t flags = 0;
  if (box.x == 0 || box.y == 0 || box.x + box.width == grey.cols ||
      box.y + box.height == grey.rows)
    flags |= kTouchesEdge;
  if (c.peak_raw >= sat) flags |= kSaturated;
  lab.forEachPixel(grey, c, [&](int x, int y, double v) { mom.add(x, y, v - b); });
  double elong = 1;
  psf = 0;
  mom.shape(elong, psf);
  if (elong > opts.max_elongation) flags |= kElongated;
  // Hot pixel: nearly all the light of the 3x3 around the peak in the peak itself.
  const cv::Rect r3 = cv::Rect(c.peak.x - 1, c.peak.y - 1, 3, 3) & frame;
  double s3 = 0;
  for (int y = r3.y; y < r3.y + r3.height; ++y)
    for (int x = r3.x; x < r3.x + r3.width; ++x) s3 += std::max(pix<T>(grey, x, y) - b, 0.0);
  if (s3 > 0 && (c.peak_raw - b) / s3 > opts.hot_pixel_fraction && !(flags & kSaturated))
    flags |= kHotPixel;
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

// Brightest first, ties in candidate order. An insertion sort: stable without
// std::stable_sort's temporary buffer (an allocation per frame), and about linear here since
// the candidates came sorted by a flux estimate already.
void sortBrightestFirst(std::vector<Centroid>& stars) {
  for (std::size_t i = 1; i < stars.size(); ++i)
    for (std::size_t j = i; j > 0 && stars[j].flux > stars[j - 1].flux; --j)
      std::swap(stars[j], stars[j - 1]);
}

template <typename T>
void measureBlobs(const cv::Mat& grey, const DetectorOptions& opts, const Centroider& main,
                  const Centroider& cog, Scratch& s, DetectionResult& res) {
  const BackgroundModel& bg = s.background;
  const BlobLabeller& lab = s.labeller;
  const double sat = saturationLevel(grey, opts);
  const std::vector<Blob>& blobs = lab.blobs();
  rankCandidates(opts, s, res);
  const std::vector<Candidate>& cands = s.candidates;
  const double min_sep2 = opts.min_separation_px * opts.min_separation_px;
  res.stars.reserve(static_cast<std::size_t>(std::min<std::size_t>(
      static_cast<std::size_t>(opts.max_stars), cands.size())));
  for (const Candidate& cand : cands) {
    if (static_cast<int>(res.stars.size()) >= opts.max_stars) break;
    const Blob& c = blobs[static_cast<std::size_t>(cand.blob)];
    const double b = bg.levelAt(c.peak.x, c.peak.y), sb = bg.sigmaAt(c.peak.x, c.peak.y);
    Moments mom;
    double psf = 0;
    const uint32_t flags = blobFlags<T>(grey, c, lab, b, sat, opts, mom, psf);
    Centroid star;
    if ((flags & opts.reject_flags) ||
        !centroidBlob<T>(grey, c, mom, b, sb, sat, psf, opts, main, cog, s, star)) {
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
  res.blobs_found = res.rejected = res.duplicates = 0;
  const double sat = saturationLevel(grey, opts);
  estimateBackground(grey, opts.background_tile_px, opts.background_samples,
                     opts.read_noise_adu, s.background);
  const BackgroundModel& bg = s.background;
  res.background = bg.level;
  res.noise_sigma = bg.sigma;
  if (bg.level >= sat) {
    res.reason = "image saturated (background at the saturation level)";
    return;
  }

  // Threshold at k sigma above the (tiled) background (seed 004 §4.1), blobs 8-connected.
  BlobLabeller& lab = s.labeller;
  const double k = opts.threshold_sigma;
  if (opts.prefilter == "none") {
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
    return;
  }
  if (grey.depth() == CV_8U)
    measureBlobs<uint8_t>(grey, opts, main, cog, s, res);
  else
    measureBlobs<uint16_t>(grey, opts, main, cog, s, res);
}

}  // namespace st::detect_detail

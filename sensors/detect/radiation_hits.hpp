/// @file radiation_hits.hpp
/// Radiation hits told from stars (issue 34). A charged particle crossing the detector leaves
/// its charge in the pixels it passes through (a dot of 1-3 px, or a short track at any
/// angle); no optics stand between, so its profile is sharper than the PSF along at least one
/// direction across it. A star's image is the PSF, the same for every star of a frame (a
/// focus that varies slowly over the field aside).
///
/// The frame's PSF, per axis: along a pixel row (x) and a column (y) through a blob's peak,
/// the Gaussian width of the three pixels (left L, peak P, right R above the background),
///   s^2 = 1 / (2 ln P - ln L - ln R)       (exact for a sampled Gaussian at any phase),
/// taken from the most significant unclipped blobs as their widest tight cluster
/// (frameWidth): the stars share one PSF, hits are sharper, so the stars set it even where
/// hits outnumber them.
/// The test, per axis: a star's two neighbours hold together at least 2 r P, r = exp(-1 /
/// (2 s^2)), the least at a peak centred on its pixel (off centre one neighbour gains more
/// than the other loses). A blob whose neighbours hold less than kNeighbourFraction of that,
/// even with kNoiseSigmas of noise in their favour, is a hit: a dot is bare along both axes,
/// a track across either axis is bare across x or y. Along the diagonals a star's two corner
/// neighbours hold at least 2 r_x r_y P (separable), and a diagonal track is bare across its
/// own diagonal. The fraction allows
/// for the cluster's width being a typical phase's, not the sharpest's, and for the focus
/// varying over the field.
/// Rows and columns are taken apart, so binned pixels (a PSF half as wide in y as in x) need
/// no camera model here; an axis whose PSF is below the pixel (r -> 0) tells nothing.
#pragma once
#include <vector>

#include <opencv2/core.hpp>

namespace st::detect_detail {

/// A blob's peak above the background and the sums of its two neighbours along x, along y
/// and along each diagonal (NaN where a neighbour is outside the image).
struct PeakProfile {
  double peak = 0, along_x = 0, along_y = 0, diagonal = 0, antidiagonal = 0;
};
PeakProfile peakProfile(const cv::Mat& grey, int px, int py, double b);

/// Three-pixel Gaussian width [px] along x and y of a profile; 0 along an axis where a
/// neighbour holds no light, a large value for a flat top.
struct AxisWidth {
  double x = 0, y = 0;
};
AxisWidth profileWidth(const cv::Mat& grey, int px, int py, double b);

/// What a hit's neighbours hold at most, as a fraction of a star's least (2 r P). Measured on
/// the 30 Swarm frames (an undersampled PSF, s ~ 0.5-0.6 px, rows binned): 0.3 flags 17 of
/// 2,236 catalog stars, 0.2 flags 3 (at the sharpest of their pixel's phase); a resolved PSF
/// (s >= 0.8 px) leaves a wide margin either way. Faint hits on an undersampled frame look
/// like faint stars and stay unflagged: ranking and verification deal with them.
constexpr double kNeighbourFraction = 0.2;
/// Noise sigmas (of the two neighbours' sum) given to the neighbours before the test.
constexpr double kNoiseSigmas = 2.0;
/// Blobs whose peak is at least this many noise sigmas set the frame's PSF.
constexpr double kPsfSettingPeakSigma = 10.0;
/// Fewer blobs than this setting the PSF: no hit is flagged (nothing to compare with).
constexpr int kMinPsfBlobs = 5;
/// At most this many of the most significant blobs are measured for the PSF.
constexpr int kMaxPsfBlobs = 60;

/// The frame's PSF widths from the significant blobs' (x, y) widths (both > 0): the stars
/// share one PSF and hits are sharper than it (tracks of one direction can form a cluster of
/// their own, as tight and as many), so the PSF is the widest cluster of the pairs (blobs
/// within kClusterTolerance of its centre along both axes) with at least a fifth of them
/// (and kMinPsfBlobs / 2 + 1), the median of its members per axis. {0, 0} when fewer than
/// kMinPsfBlobs pairs or no such cluster.
AxisWidth frameWidth(const std::vector<AxisWidth>& blobs);

/// Relative width difference within which two blobs count as the same PSF: a star's
/// three-pixel width moves by up to ~15 % with its sub-pixel phase.
constexpr double kClusterTolerance = 0.2;

/// True when the profile's neighbours along x or y hold less than a star of the frame's PSF
/// widths (psf_x, psf_y; 0 = unknown) allows, with noise `sigma` [ADU] per pixel.
bool sharperThanPsf(const PeakProfile& p, double sigma, double psf_x, double psf_y);

}  // namespace st::detect_detail

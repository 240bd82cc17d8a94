// magnitude-error: how well the detector's flux gives back a star's visual magnitude, seed 004
// sec. 5.3, Fig. 5.3 and Table 5.3. In the seed's experiment twenty stars of one magnitude
// (V = 0..4) are put at random places of a 1280 x 1024 image taken with the camera of its
// Table 5.2 (D = 20 mm, t = 0.1 s, gain 10 e-/ADU, psfWidth 10 px, read 41 e-, dark 40 e-,
// 5 sigma threshold), centroided, and the magnitude is computed again from the measured
// intensity; only sets where all twenty stars were centroided correctly count.
// Here one trial = one such image per magnitude (the same twenty positions for every V),
// exposed by the project's simulator (sensors/sim) and detected by sensors/detect, with the
// weighted sum (`cog`) and the maximum-likelihood fit (`gauss`). The magnitude is
//   V_calc = -2.5 log10(flux_e / electrons of a V = 0 star)  (seed 004 eq. 3.4 inverted),
// and the table reports the mean and standard deviation of V_calc - V.
#include <algorithm>
#include <cmath>
#include <map>

#include "app/montecarlo/seed004_psf.hpp"
#include "app/montecarlo/experiments.hpp"
#include "app/montecarlo/stats.hpp"
#include "common/errors.hpp"
#include "sensors/detect/star_detector.hpp"
#include "sensors/sim/detector.hpp"
#include "sensors/sim/psf.hpp"
#include "sensors/sim/sensor_params.hpp"

namespace st::app::mc {
namespace {

const std::vector<double> kMags = {0, 1, 2, 3, 4};  // seed 004 Table 5.3
// Seed 004 Table 5.3: mean and standard deviation of the difference, per V above (its WS).
const std::vector<double> kPaperMean = {0.0309, 0.0311, 0.0353, 0.0552, 0.1362};
const std::vector<double> kPaperStd = {0.0427, 0.0324, 0.0419, 0.0414, 0.0685};
const std::vector<std::string> kCentroiders = {"cog", "gauss"};
constexpr int kStarsPerImage = 20;
constexpr double kPsfWidthPx = 10;  // Table 5.2 psfWidth
// A star counts as "centroided correctly" within this distance of its true place [px]; the
// centroid error of a V = 4 star here is ~0.1 px, a wrong blob is > 10 px away.
constexpr double kMatchPx = 2.0;

// The camera of seed 004 Table 5.2 in the seed's own photometry:
//  - eq. 3.4, electrons = a FFSR t 10^((28 - V) / 2.5) with a = pi 0.01^2 m^2, FFSR 0.12,
//    t = 0.1 s (read without the ADC gain g, which the seed applies at the ADC; with it a
//    V = 6 star would still pass 5 sigma, against the seed's "could not be obtained for
//    M_V > 4 without the noise floor being dropped below the 5 sigma value");
//  - eq. 4.13, sigma of the PSF = psfWidth / 4.
// Written through the simulator's parameters: F0 (pi D^2 / 4) T QE t with T = QE = 1 and
// F0 = FFSR 10^(28 / 2.5).
SensorParams tableCamera() {
  SensorParams s;
  s.aperture_diameter_m = 0.02;  // a = pi 0.01^2 m^2
  s.transmission = 1;
  s.qe = 1;
  s.v0_photon_flux = 0.12 * std::pow(10.0, 28 / 2.5);
  s.exposure_s = 0.1;
  s.psf_sigma_px = seed004PsfSigma(kPsfWidthPx);
  s.sky_e_px_s = 0;
  s.dark_current_e_px_s = 40 / s.exposure_s;  // DK = 40 e-
  s.read_noise_e = 410 * s.exposure_s;        // RO = 410 t_shutter e-
  s.gain_e_per_adu = 10;
  s.bit_depth = 16;
  s.full_well_e = 6.0e5;  // the V = 0 peak (~1.5e4 e-) stays far below it and the ADC's top
  s.bias_adu = 100;
  s.hot_pixels = 0;
  return s;
}

class MagnitudeError : public Experiment {
 public:
  std::string name() const override { return "magnitude-error"; }
  bool usesFieldStop() const override { return false; }
  void configure(McOptions& o) const override {
    if (o.width < 200 || o.height < 200)
      throw InputError("--size: magnitude-error needs at least 200 x 200 px for its " +
                       std::to_string(kStarsPerImage) + " stars of psfWidth 10 px");
  }
  std::vector<std::string> columns(const McOptions&) const override {
    return {"trial", "V", "centroider", "star", "found", "dpos_px", "V_calc"};
  }
  void prepare(const McOptions&) override {}

  std::unique_ptr<TrialWorker> makeWorker(const McOptions& o) const override {
    struct W : TrialWorker {
      McOptions o;
      SensorParams cam = tableCamera();
      std::unique_ptr<Detector> sensor;
      std::vector<std::unique_ptr<StarDetector>> dets;
      void run(uint64_t trial, uint64_t seed, std::vector<Row>& rows) override {
        std::mt19937_64 rng(seed);
        // Twenty places, the whole PSF (+-3.5 sigma) on the chip, no two closer than 4
        // psfWidth (the seed kept to twenty stars so that they would rarely overlap).
        const double margin = 3.5 * cam.psf_sigma_px;
        std::uniform_real_distribution<double> ux(margin, o.width - 1 - margin),
            uy(margin, o.height - 1 - margin);
        std::vector<Vec2> at;
        while (static_cast<int>(at.size()) < kStarsPerImage) {
          const Vec2 p(ux(rng), uy(rng));
          bool clear = true;
          for (const Vec2& q : at) clear = clear && (p - q).norm() > 4 * kPsfWidthPx;
          if (clear) at.push_back(p);
        }
        const double e0 = cam.starElectrons(0);
        for (double v : kMags) {
          cv::Mat electrons = sensor->meanBackground();
          for (const Vec2& p : at) addGaussianStar(electrons, p, cam.starElectrons(v), cam.psf_sigma_px);
          const cv::Mat image = sensor->expose(electrons, rng);
          for (std::size_t k = 0; k < dets.size(); ++k) {
            const DetectionResult det = dets[k]->detect(image);
            for (int s = 0; s < kStarsPerImage; ++s) {
              const Centroid* best = nullptr;
              double d_best = kMatchPx;
              for (const Centroid& c : det.stars) {
                const double d = (c.px - at[s]).norm();
                if (d <= d_best) {
                  d_best = d;
                  best = &c;
                }
              }
              const bool ok = best && best->flux > 0;
              rows.push_back({std::to_string(trial), fmt(v, 3), kCentroiders[k], std::to_string(s),
                              ok ? "1" : "0", fmt(ok ? d_best : NAN, 5),
                              fmt(ok ? -2.5 * std::log10(best->flux * cam.gain_e_per_adu / e0) : NAN, 7)});
            }
          }
        }
      }
    };
    auto w = std::make_unique<W>();
    w->o = o;
    w->sensor = std::make_unique<Detector>(w->cam, o.width, o.height);
    for (const std::string& c : kCentroiders) {
      DetectorOptions d;
      d.gain_e_per_adu = w->cam.gain_e_per_adu;
      d.read_noise_adu = w->cam.read_noise_e / w->cam.gain_e_per_adu;
      d.threshold_sigma = 5;  // Table 5.2: noise threshold 5 sigma
      d.centroider = c;
      d.max_psf_sigma_px = 1.5 * w->cam.psf_sigma_px;  // the defocused PSF is a star here
      d.max_area = 20000;
      w->dets.push_back(std::make_unique<StarDetector>(d));
    }
    return w;
  }

  Report summarise(const McOptions& o, const Table& t) const override {
    Report rep;
    rep.title = "Assigned vs measured magnitude (seed 004 Table 5.3), " + std::to_string(o.width) +
                "x" + std::to_string(o.height) + " px, camera of seed 004 Table 5.2";
    rep.notes.push_back(
        "Each trial exposes one image per magnitude V = 0..4 with " +
        std::to_string(kStarsPerImage) + " stars of that magnitude at random places (whole "
        "PSF on the chip, no two within 4 psfWidth), Gaussian PSF of sigma = psfWidth / 4 = "
        "2.5 px (seed eq. 4.13), electrons = a FFSR t 10^((28 - V) / 2.5) (seed eq. 3.4), dark "
        "40 e-, read 41 e-, gain 10 e-/ADU, 16-bit ADC, 5 sigma threshold; detection and "
        "centroiding by "
        "sensors/detect with `cog` (weighted sum over the centroid window) or `gauss` "
        "(maximum-likelihood PSF fit). V_calc = -2.5 log10(measured electrons / electrons of "
        "a V = 0 star). As in the seed, only images where all " + std::to_string(kStarsPerImage) +
        " stars were found within " + fmt(kMatchPx, 2) + " px of their true place count.");
    const std::size_t cv = t.col("V"), cc = t.col("centroider"), ct = t.col("trial"),
                      cf = t.col("found"), cm = t.col("V_calc");
    // (V, centroider, trial) -> the image's differences, and whether every star was found.
    struct Image {
      std::vector<double> diff;
      bool all = true;
    };
    std::map<std::tuple<double, std::string, std::string>, Image> images;
    for (const Row& r : t.rows) {
      Image& im = images[{cellNum(r, cv), r[cc], r[ct]}];
      if (r[cf] != "1") {
        im.all = false;
        continue;
      }
      im.diff.push_back(cellNum(r, cm) - cellNum(r, cv));
    }
    ReportTable tab;
    tab.name = "table5_3";
    tab.caption = "Table 5.3: V_calc - V per magnitude (images with all stars found)";
    tab.table.columns = {"V", "centroider", "images", "images_all_found", "stars",
                         "mean_diff", "std_diff", "mean_abs_diff", "paper_mean", "paper_std"};
    Plot p = makePlot("Measured - assigned magnitude (seed 004 Table 5.3)", "assigned V",
                      "mean of V_calc - V (error bars: 1 std)");
    p.key = "top left";
    PlotSeries paper("paper (seed 004 Table 5.3)", PlotStyle::ErrorBars);
    for (std::size_t k = 0; k < kMags.size(); ++k) {
      paper.x.push_back(kMags[k]);
      paper.y.push_back(kPaperMean[k]);
      paper.y_lo.push_back(kPaperMean[k] - kPaperStd[k]);
      paper.y_hi.push_back(kPaperMean[k] + kPaperStd[k]);
    }
    p.series.push_back(paper);
    for (const std::string& cen : kCentroiders) {
      PlotSeries s(cen, PlotStyle::ErrorBars);
      for (std::size_t k = 0; k < kMags.size(); ++k) {
        const double v = kMags[k];
        std::size_t n_img = 0, n_all = 0;
        std::vector<double> d, a;
        for (const auto& [key, im] : images) {
          if (std::get<0>(key) != v || std::get<1>(key) != cen) continue;
          ++n_img;
          if (!im.all) continue;
          ++n_all;
          for (double x : im.diff) {
            d.push_back(x);
            a.push_back(std::fabs(x));
          }
        }
        if (n_img == 0) continue;
        const double mu = mean(d);
        double var = 0;
        for (double x : d) var += (x - mu) * (x - mu);
        const double sd = d.size() > 1 ? std::sqrt(var / double(d.size() - 1)) : NAN;
        tab.table.rows.push_back({fmt(v, 3), cen, std::to_string(n_img), std::to_string(n_all),
                                  std::to_string(d.size()), fmt(mu, 4), fmt(sd, 4),
                                  fmt(mean(a), 4), fmt(kPaperMean[k], 4), fmt(kPaperStd[k], 4)});
        s.x.push_back(v);
        s.y.push_back(mu);
        s.y_lo.push_back(mu - sd);
        s.y_hi.push_back(mu + sd);
      }
      p.series.push_back(s);
    }
    rep.tables.push_back(tab);
    rep.plots.push_back({"table5_3", p});
    return rep;
  }
};

}  // namespace

std::unique_ptr<Experiment> makeMagnitudeError() { return std::make_unique<MagnitudeError>(); }

}  // namespace st::app::mc

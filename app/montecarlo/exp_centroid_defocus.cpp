// centroid-defocus: the centroider design studies of seed 004 sec. 4.2.2. Fig. 4.4: centroid
// error vs PSF width without noise; Fig. 4.5: the same at several SNRs, whose knee is the
// best defocus for that SNR; Table 4.2: time of the weighted-sum (our "cog") and maximum-
// likelihood (our "gauss") centroiders per magnitude in the camera of Table 4.1.
// Each trial puts one star at a uniformly random sub-pixel position and measures it with
// each centroider on a window of +-max(3, 3 sigma) px around the true position's pixel.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <set>

#include "app/montecarlo/experiments.hpp"
#include "app/montecarlo/stats.hpp"
#include "common/errors.hpp"
#include "sensors/detect/centroider.hpp"
#include "app/montecarlo/seed004_psf.hpp"
#include "sensors/sim/psf.hpp"
#include "sensors/sim/sensor_params.hpp"

namespace st::app::mc {
namespace {

using Clock = std::chrono::steady_clock;

// PSF widths: seed 004's psfWidth, 4 sigma of the Gaussian PSF (eq. 4.13; Tables 4.1, 7.1:
// 10 px), the x axis of Figs. 4.4-4.5.
const std::vector<double> kPsfWidths = {1, 2, 3, 4, 5, 6, 8, 10, 12, 15};
// SNR as seed 004 ch. 3 counts it, per pixel: the star's peak pixel (centred) over the
// background noise. 0 = no noise (Fig. 4.4).
const std::vector<double> kSnr = {0, 1, 3, 10, 30};
const std::vector<std::string> kCentroiders = {"cog", "gauss"};
// Table 4.1's camera: gain 10 e-/ADU, t 0.1 s, a = 3.14e-4 m^2 (D = 20 mm), DK 41 e-,
// RO 40 e-, psfWidth 10 px, M_V 1..5.
constexpr double kTablePsfWidth = 10, kGain = 10, kDarkE = 41, kReadE = 40;
const std::vector<double> kTableMags = {1, 2, 3, 4, 5};
constexpr double kBackgroundAdu = 100;

struct Case {
  std::string kind;  ///< "fig" (Figs. 4.4-4.5) or "table" (Table 4.2)
  double psf_width, snr, mag;
};

std::vector<Case> cases() {
  std::vector<Case> c;
  for (double s : kSnr)
    for (double w : kPsfWidths) c.push_back({"fig", w, s, NAN});
  for (double m : kTableMags) c.push_back({"table", kTablePsfWidth, NAN, m});
  return c;
}

class CentroidDefocus : public Experiment {
 public:
  std::string name() const override { return "centroid-defocus"; }
  bool measuresTime() const override { return true; }
  bool usesFieldStop() const override { return false; }
  void configure(McOptions&) const override {}
  std::vector<std::string> columns(const McOptions&) const override {
    return {"trial", "kind", "psf_width_px", "snr", "mag", "centroider", "ok", "dx_px", "dy_px", "us"};
  }
  void prepare(const McOptions&) override {}

  std::unique_ptr<TrialWorker> makeWorker(const McOptions&) const override {
    struct W : TrialWorker {
      std::vector<std::unique_ptr<Centroider>> cents;
      SensorParams table_cam;
      W() {
        for (const auto& n : kCentroiders) cents.push_back(Centroider::create(n));
        table_cam.aperture_diameter_m = 0.02;
        table_cam.exposure_s = 0.1;
      }
      void run(uint64_t trial, uint64_t seed, std::vector<Row>& rows) override {
        std::mt19937_64 rng(seed);
        std::uniform_real_distribution<double> u(0.0, 1.0);
        std::normal_distribution<double> g(0.0, 1.0);
        for (const Case& c : cases()) {
          const double sigma = seed004PsfSigma(c.psf_width);
          const int half = std::max(3, static_cast<int>(std::ceil(3 * sigma)));
          const int side = 2 * half + 1;
          // The star near the window's centre pixel, anywhere within it.
          const Vec2 truth(half + u(rng) - 0.5, half + u(rng) - 0.5);
          double flux_adu, sigma_bg_adu, gain = kGain;
          bool noise = true;
          if (c.kind == "table") {
            flux_adu = table_cam.starElectrons(c.mag) / kGain;
            sigma_bg_adu = std::sqrt(kDarkE + kReadE * kReadE) / kGain;
          } else {
            sigma_bg_adu = 10;
            noise = c.snr > 0;
            // Peak of a centred star = snr * sigma_bg (for no noise: the SNR 10 star).
            const double peak = (noise ? c.snr : 10.0) * sigma_bg_adu;
            flux_adu = peak * 2 * M_PI * sigma * sigma;
          }
          cv::Mat e = cv::Mat::zeros(side, side, CV_64F);
          addGaussianStar(e, truth, flux_adu, sigma);
          StarPatch p;
          p.values = cv::Mat1f(side, side);
          for (int y = 0; y < side; ++y)
            for (int x = 0; x < side; ++x) {
              const double s = e.at<double>(y, x);
              double v = kBackgroundAdu + s;
              if (noise) v += g(rng) * std::sqrt(sigma_bg_adu * sigma_bg_adu + s / gain);
              p.values(y, x) = static_cast<float>(v);
            }
          p.background = kBackgroundAdu;
          p.sigma_bg = noise ? sigma_bg_adu : 1e-3 * sigma_bg_adu;
          p.gain = gain;
          p.psf_sigma = sigma;
          p.guess = Vec2(half, half);
          for (std::size_t k = 0; k < cents.size(); ++k) {
            Centroid out;
            const auto t0 = Clock::now();
            const bool ok = cents[k]->centroid(p, out);
            const double us = std::chrono::duration<double, std::micro>(Clock::now() - t0).count();
            rows.push_back({std::to_string(trial), c.kind, fmt(c.psf_width, 4), fmt(c.snr, 4),
                            fmt(c.mag, 3), kCentroiders[k], ok ? "1" : "0",
                            fmt(ok ? out.px.x() - truth.x() : NAN, 6),
                            fmt(ok ? out.px.y() - truth.y() : NAN, 6), fmt(us, 4)});
          }
        }
      }
    };
    return std::make_unique<W>();
  }

  Report summarise(const McOptions& o, const Table& t) const override {
    Report rep;
    rep.title = "Centroid accuracy vs PSF width and SNR; centroider time per magnitude (seed 004 Figs. 4.4-4.5, Table 4.2)";
    rep.notes.push_back(
        "One star per trial at a uniformly random sub-pixel position, Gaussian PSF integrated "
        "over the pixels, measured on a +-max(3, 3 sigma) px window around the pixel of the "
        "window centre by `cog` (intensity-weighted centre of gravity, the seed's weighted "
        "sum) and `gauss` (maximum-likelihood fit of the PSF, the seed's MLE). PSF width = "
        "seed 004's psfWidth, 4 sigma of the Gaussian (eq. 4.13); SNR = the peak pixel of a centred star over the background noise per pixel "
        "(10 ADU), star shot noise at 10 e-/ADU; SNR 0 = no noise (Fig. 4.4, star of peak "
        "100 ADU). Error = radial RMS of (estimate - truth) over the trials that gave a "
        "centroid. Table 4.2 rows: the camera of seed 004 Table 4.1 (D = 20 mm, t = 0.1 s, "
        "dark 41 e-, read 40 e-, gain 10 e-/ADU, psfWidth 10 px) with this project's "
        "photometry (sensors/sim/sensor_params.hpp, eq. 3.4). Times are one call of the "
        "centroider, median, on this machine (" + std::to_string(o.runs) + " trials).");
    const std::size_t ck = t.col("kind"), cw = t.col("psf_width_px"), cs = t.col("snr"),
                      cm = t.col("mag"), cc = t.col("centroider"), co = t.col("ok"),
                      cx = t.col("dx_px"), cy = t.col("dy_px"), cu = t.col("us");
    struct Acc {
      std::vector<double> r2, us;
      std::size_t n = 0, ok = 0;
    };
    std::map<std::tuple<std::string, double, double, double, std::string>, Acc> acc;
    for (const Row& r : t.rows) {
      const double mag = r[cm] == "nan" ? NAN : cellNum(r, cm);
      const double snr = r[cs] == "nan" ? NAN : cellNum(r, cs);
      auto& a = acc[{r[ck], cellNum(r, cw), std::isnan(snr) ? -1 : snr, std::isnan(mag) ? -1 : mag, r[cc]}];
      ++a.n;
      a.us.push_back(cellNum(r, cu));
      if (r[co] != "1") continue;
      ++a.ok;
      const double dx = cellNum(r, cx), dy = cellNum(r, cy);
      a.r2.push_back(dx * dx + dy * dy);
    }
    auto rmsOf = [](const Acc& a) { return a.r2.empty() ? NAN : std::sqrt(mean(a.r2)); };

    ReportTable fig;
    fig.name = "accuracy";
    fig.caption = "Figs. 4.4-4.5: radial RMS centroid error [px] vs PSF width (psfWidth = 4 sigma) and SNR";
    fig.table.columns = {"snr", "psf_width_px", "centroider", "trials", "ok_%", "rms_px", "median_us"};
    ReportTable knee;
    knee.name = "knee";
    knee.caption = "Best defocus per SNR: the narrowest PSF within 10 % of the smallest error (widths where >= 95 % of the stars gave a centroid)";
    knee.table.columns = {"snr", "centroider", "width_min_error_px", "min_rms_px", "width_knee_px", "rms_at_knee_px"};
    std::vector<ReportPlot> plots;
    for (const std::string& cen : kCentroiders) {
      Plot p = makePlot("Centroid error vs PSF width, " + cen, "PSF width, 4 sigma [px]", "radial RMS error [px]");
      p.log_y = true;
      for (double s : kSnr) {
        PlotSeries ser(s > 0 ? "SNR " + fmt(s, 3) : "no noise", PlotStyle::LinesPoints);
        // Only widths where nearly every star gave a centroid: an error averaged over the few
        // that converged says nothing about the width.
        std::vector<std::pair<double, double>> curve;
        for (double w : kPsfWidths) {
          const auto it = acc.find({"fig", w, s, -1, cen});
          if (it == acc.end()) continue;
          const Acc& a = it->second;
          const double e = rmsOf(a);
          fig.table.rows.push_back({fmt(s, 3), fmt(w, 3), cen, std::to_string(a.n),
                                    fmt(100.0 * double(a.ok) / double(a.n), 4), fmt(e, 4),
                                    fmt(quantile(a.us, 0.5), 3)});
          ser.x.push_back(w);
          ser.y.push_back(e);
          if (a.ok >= 0.95 * double(a.n)) curve.push_back({w, e});
        }
        p.series.push_back(ser);
        if (curve.empty()) continue;
        const auto best = *std::min_element(curve.begin(), curve.end(), [](auto a, auto b) { return a.second < b.second; });
        auto k = best;
        for (const auto& pt : curve)
          if (pt.second <= 1.1 * best.second) { k = pt; break; }
        knee.table.rows.push_back({fmt(s, 3), cen, fmt(best.first, 3), fmt(best.second, 4), fmt(k.first, 3), fmt(k.second, 4)});
      }
      plots.push_back({"accuracy_" + cen, p});
    }
    ReportTable tab;
    tab.name = "table4_2";
    tab.caption = "Table 4.2: centroider time and error per magnitude (Table 4.1 camera, psfWidth 10 px = 4 sigma)";
    tab.table.columns = {"V", "centroider", "trials", "ok_%", "rms_px", "median_us", "time_ratio_to_cog"};
    for (double m : kTableMags) {
      const auto base = acc.find({"table", kTablePsfWidth, -1, m, "cog"});
      const double base_us = base == acc.end() ? NAN : quantile(base->second.us, 0.5);
      for (const std::string& cen : kCentroiders) {
        const auto it = acc.find({"table", kTablePsfWidth, -1, m, cen});
        if (it == acc.end()) continue;
        const Acc& a = it->second;
        const double us = quantile(a.us, 0.5);
        tab.table.rows.push_back({fmt(m, 3), cen, std::to_string(a.n),
                                  fmt(100.0 * double(a.ok) / double(a.n), 4), fmt(rmsOf(a), 4),
                                  fmt(us, 3), fmt(us / base_us, 3)});
      }
    }
    rep.tables = {fig, knee, tab};
    rep.plots = plots;
    return rep;
  }
};

}  // namespace

std::unique_ptr<Experiment> makeCentroidDefocus() { return std::make_unique<CentroidDefocus>(); }

}  // namespace st::app::mc

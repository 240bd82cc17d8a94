// star-count: how many catalog stars the camera sees over random attitudes, for each
// magnitude limit. Seed 000 Fig. 1 (histogram over NT = 1000 random attitudes) and seed 004
// Fig. 5.1/5.2 (average and minimum number of stars for a given M_V and FOV).
#include <algorithm>
#include <cmath>
#include <map>

#include "app/montecarlo/experiments.hpp"
#include "app/montecarlo/sky.hpp"
#include "app/montecarlo/stats.hpp"
#include "common/conventions.hpp"
#include "common/errors.hpp"

namespace st::app::mc {
namespace {

std::string magColumn(double m) { return "n_V" + fmt(m, 4); }

class StarCount : public Experiment {
 public:
  std::string name() const override { return "star-count"; }

  void configure(McOptions& o) const override {
    if (std::find(o.mags.begin(), o.mags.end(), o.mag_limit) == o.mags.end())
      o.mags.push_back(o.mag_limit);
    std::sort(o.mags.begin(), o.mags.end());
    o.mags.erase(std::unique(o.mags.begin(), o.mags.end()), o.mags.end());
  }

  std::vector<std::string> columns(const McOptions& o) const override {
    std::vector<std::string> c = {"trial", "ra_deg", "dec_deg"};
    for (double m : o.mags) c.push_back(magColumn(m));
    return c;
  }

  void prepare(const McOptions& o) override {
    db_ = buildDatabase(o, deg2rad(1.0), o.mags.back());
    // A limit beyond the catalog's depth would only repeat the row of the depth: refuse it
    // rather than print rows that look like a measurement.
    const BuildReport& r = db_->report();
    std::string beyond;
    for (double m : o.mags)
      if (m > r.catalog_depth_vmag) beyond += (beyond.empty() ? "" : ", ") + fmt(m, 4);
    if (!beyond.empty())
      throw InputError("star-count: magnitude limit(s) " + beyond + " (--mags/--mag-limit) lie " +
                       "beyond the depth of " + r.catalog_path + " (V " +
                       fmt(r.catalog_depth_vmag, 4) + "): their rows would repeat the V " +
                       fmt(r.catalog_depth_vmag, 4) + " row. Use limits <= " +
                       fmt(r.catalog_depth_vmag, 4) +
                       " or a deeper --catalog (hip_main.dat, tyc2.dat)");
    cam_ = makeCamera(o);
  }

  std::unique_ptr<TrialWorker> makeWorker(const McOptions& o) const override {
    struct W : TrialWorker {
      const StarCount* e;
      std::vector<double> mags;
      double stop = 0;
      void run(uint64_t trial, uint64_t seed, std::vector<Row>& rows) override {
        std::mt19937_64 rng(seed);
        const Quat q = randomAttitude(rng);
        const auto vis = visibleStars(*e->db_, e->cam_, q, mags.back(), stop);
        const RaDecRoll rdr = raDecRollFromAttitude(q);
        Row r = {std::to_string(trial), fmt(rad2deg(rdr.ra), 7), fmt(rad2deg(rdr.dec), 7)};
        for (double m : mags)
          r.push_back(std::to_string(std::count_if(
              vis.begin(), vis.end(), [m](const VisibleStar& v) { return v.mag <= m; })));
        rows.push_back(std::move(r));
      }
    };
    auto w = std::make_unique<W>();
    w->e = this;
    w->mags = o.mags;
    w->stop = fieldStop(o);
    return w;
  }

  Report summarise(const McOptions& o, const Table& t) const override {
    Report rep;
    rep.title = "Stars in the field of view over random attitudes (" + fmt(o.fov_deg, 4) +
                " deg horizontal FOV, " + std::to_string(o.width) + "x" +
                std::to_string(o.height) + " px" +
                (o.field_stop_deg > 0 ? ", circular field stop " + fmt(o.field_stop_deg, 4) + " deg"
                                      : std::string()) + ")";
    rep.notes.push_back(
        "Each trial draws a uniformly distributed attitude and counts the database stars "
        "(double stars closer than " + fmt(o.merge_arcsec, 3) + "\" merged) that project inside "
        "the image, for each magnitude limit. Seed 000 Fig. 1 is the histogram for one limit; "
        "seed 004 Fig. 5.1/5.2 the average and minimum per limit. `min` is the minimum over "
        "the trials, not over the whole sky.");
    // Per magnitude: the statistics of N.
    ReportTable per;
    per.name = "per_mag";
    per.caption = "Stars per image vs magnitude limit";
    per.table.columns = {"V_limit", "trials", "mean", "std", "min", "p1", "p5", "median",
                         "max", "P(N<3)", "P(N<4)"};
    Plot pm = makePlot("Stars per image vs magnitude limit (" + fmt(o.fov_deg, 4) + " deg FOV)",
                       "magnitude limit V", "stars in the image");
    pm.log_y = true;
    pm.key = "top left";
    PlotSeries s_mean{"mean", PlotStyle::LinesPoints}, s_band{"5 % .. 95 %", PlotStyle::Band},
        s_min{"minimum over the trials", PlotStyle::LinesPoints}, s_p1{"1 % quantile", PlotStyle::LinesPoints};
    std::vector<double> main_counts;
    for (double m : o.mags) {
      const std::size_t c = t.col(magColumn(m));
      std::vector<double> n;
      for (const Row& r : t.rows) n.push_back(cellNum(r, c, t.columns[c]));
      if (m == o.mag_limit) main_counts = n;
      const double mu = mean(n);
      double var = 0;
      for (double x : n) var += (x - mu) * (x - mu);
      const double sd = n.size() > 1 ? std::sqrt(var / double(n.size() - 1)) : 0;
      const double lt3 = double(std::count_if(n.begin(), n.end(), [](double x) { return x < 3; }));
      const double lt4 = double(std::count_if(n.begin(), n.end(), [](double x) { return x < 4; }));
      per.table.rows.push_back({fmt(m, 4), std::to_string(n.size()), fmt(mu, 4), fmt(sd, 3),
                                fmt(quantile(n, 0), 4), fmt(quantile(n, 0.01), 4),
                                fmt(quantile(n, 0.05), 4), fmt(quantile(n, 0.5), 4),
                                fmt(quantile(n, 1), 4), fmt(lt3 / double(n.size()), 4),
                                fmt(lt4 / double(n.size()), 4)});
      for (auto* s : {&s_mean, &s_band, &s_min, &s_p1}) s->x.push_back(m);
      s_mean.y.push_back(mu);
      s_band.y.push_back(mu);
      s_band.y_lo.push_back(std::max(0.5, quantile(n, 0.05)));
      s_band.y_hi.push_back(quantile(n, 0.95));
      s_min.y.push_back(std::max(0.5, quantile(n, 0)));
      s_p1.y.push_back(std::max(0.5, quantile(n, 0.01)));
    }
    pm.series = {s_band, s_mean, s_p1, s_min};
    rep.tables.push_back(per);

    // Seed 004 Table 5.1: the faintest limit a camera needs so that every image holds at
    // least N stars, i.e. the smallest grid limit whose minimum over the trials is >= N.
    ReportTable req;
    req.name = "required_mag";
    req.caption = "Smallest magnitude limit of the grid with at least N stars in every trial "
                  "(seed 004 Table 5.1)";
    req.table.columns = {"min_stars", "required_V", "min_at_required_V"};
    for (int n_min : {3, 4, 5, 6, 8}) {
      std::string v = "> grid", got = "";
      for (std::size_t k = 0; k < o.mags.size(); ++k) {
        const double lowest = cellNum(per.table.rows[k], 4, "min");
        if (lowest >= n_min) {
          v = fmt(o.mags[k], 4);
          got = fmt(lowest, 4);
          break;
        }
      }
      req.table.rows.push_back({std::to_string(n_min), v, got});
    }
    rep.tables.push_back(req);

    // Histogram at the main magnitude limit.
    ReportTable hist;
    hist.name = "histogram";
    hist.caption = "Histogram of stars per image, V <= " + fmt(o.mag_limit, 4);
    hist.table.columns = {"stars", "trials", "fraction", "cumulative"};
    std::map<int, std::size_t> h;
    for (double x : main_counts) ++h[static_cast<int>(x)];
    std::size_t cum = 0;
    PlotSeries bars{"trials", PlotStyle::Boxes};
    const int max_n = h.empty() ? 0 : h.rbegin()->first;
    for (int k = 0; k <= max_n; ++k) {
      const std::size_t c = h.count(k) ? h[k] : 0;
      cum += c;
      hist.table.rows.push_back({std::to_string(k), std::to_string(c),
                                 fmt(double(c) / double(main_counts.size()), 4),
                                 fmt(double(cum) / double(main_counts.size()), 4)});
      bars.x.push_back(k);
      bars.y.push_back(double(c));
    }
    rep.tables.push_back(hist);
    Plot ph = makePlot("Stars per image, V <= " + fmt(o.mag_limit, 4) + ", " + fmt(o.fov_deg, 4) +
                           " deg FOV, " + std::to_string(main_counts.size()) +
                           " random attitudes",
                       "stars in the image", "trials");
    ph.key = "off";
    ph.x_min = -0.5;
    ph.series = {bars};
    rep.plots.push_back({"histogram", ph});
    rep.plots.push_back({"per_mag", pm});
    return rep;
  }

 private:
  std::shared_ptr<const StarDatabase> db_;
  CameraModel cam_;
};

}  // namespace

std::unique_ptr<Experiment> makeStarCount() { return std::make_unique<StarCount>(); }

}  // namespace st::app::mc

// error-vs-stars: attitude error vs the number of matched stars, per Wahba solver, against
// the solver's own covariance (attitudeSigma of cov_body) and the rule of thumb of seed 003
// (sigma_axis ~= sigma_star / sqrt(N), Fig. 18); seed 000 Fig. 12 plots the maximum error
// vs the number of stars. Correspondences are known (no identification), so only the
// estimation is measured.
//
// Per trial: a random attitude, the visible stars in a random order with pixel noise drawn
// once; for each N in the grid the first N of them (nested subsets) go to every solver.
#include <algorithm>
#include <cmath>
#include <map>

#include "app/montecarlo/experiments.hpp"
#include "app/montecarlo/sky.hpp"
#include "app/montecarlo/stats.hpp"
#include "common/conventions.hpp"
#include "common/errors.hpp"
#include "sensors/attitude/wahba.hpp"
#include "sensors/identify/star_observation.hpp"

namespace st::app::mc {
namespace {

const std::vector<int> kStarCounts = {2, 3, 4, 5, 6, 8, 10, 12, 15, 20, 25, 30, 40, 50};

class ErrorVsStars : public Experiment {
 public:
  std::string name() const override { return "error-vs-stars"; }

  void configure(McOptions& o) const override {
    if (o.solvers.empty()) o.solvers = WahbaSolver::names();
    for (const std::string& s : o.solvers) {
      std::string err;
      if (!WahbaSolver::create(s, &err)) throw InputError("--solvers: " + err);
    }
    if (o.noise_px <= 0) throw InputError("--noise-px must be > 0 for error-vs-stars");
  }

  std::vector<std::string> columns(const McOptions&) const override {
    return {"trial", "n_stars", "solver", "ok", "err_cross_arcsec", "err_roll_arcsec",
            "err_total_arcsec", "sigma_cross_arcsec", "sigma_roll_arcsec", "nees"};
  }

  void prepare(const McOptions& o) override {
    cam_ = makeCamera(o);
    db_ = buildDatabase(o, deg2rad(1.0), o.mag_limit);
  }

  std::unique_ptr<TrialWorker> makeWorker(const McOptions& o) const override {
    struct W : TrialWorker {
      const ErrorVsStars* e;
      McOptions o;
      std::vector<std::unique_ptr<WahbaSolver>> solvers;
      void run(uint64_t trial, uint64_t seed, std::vector<Row>& rows) override {
        std::mt19937_64 rng(seed);
        const Quat q = randomAttitude(rng);
        auto vis = visibleStars(*e->db_, e->cam_, q, o.mag_limit, fieldStop(o));
        std::shuffle(vis.begin(), vis.end(), rng);
        std::normal_distribution<double> n01;
        std::vector<Centroid> cents;
        for (const VisibleStar& v : vis) {
          Centroid c{};
          c.px = v.px + o.noise_px * Vec2(n01(rng), n01(rng));
          c.cov_px = o.noise_px * o.noise_px * Mat2::Identity();
          cents.push_back(c);
        }
        const auto obs = toStarObservations(cents, e->cam_, 0.0);
        std::vector<VectorObservation> vo;
        for (int n : kStarCounts) {
          if (n > static_cast<int>(obs.size())) break;
          vo.clear();
          for (int k = 0; k < n; ++k)
            vo.push_back({obs[k].v_cam, e->db_->stars()[vis[k].star].u_i, obs[k].sigma});
          for (const auto& s : solvers) {
            const WahbaSolution sol = s->solve(vo);
            Row r = {std::to_string(trial), std::to_string(n), s->name(), sol.ok ? "1" : "0"};
            if (sol.ok) {
              const AttitudeError err = attitudeError(sol.q_ib, q);
              const AttitudeSigma sig = attitudeSigma(sol.cov_body);
              r.insert(r.end(), {fmt(rad2arcsec(err.cross_boresight), 6),
                                 fmt(rad2arcsec(err.roll), 6), fmt(rad2arcsec(err.total), 6),
                                 fmt(rad2arcsec(sig.cross_boresight), 6),
                                 fmt(rad2arcsec(sig.roll), 6),
                                 fmt(attitudeNees(sol.q_ib, sol.cov_body, q), 6)});
            } else {
              r.insert(r.end(), {"nan", "nan", "nan", "nan", "nan", "nan"});
            }
            rows.push_back(std::move(r));
          }
        }
        if (obs.size() < 2)  // keep one row per trial so every trial is accounted for
          rows.push_back({std::to_string(trial), std::to_string(obs.size()), "-", "0", "nan",
                          "nan", "nan", "nan", "nan", "nan"});
      }
    };
    auto w = std::make_unique<W>();
    w->e = this;
    w->o = o;
    for (const std::string& s : o.solvers) w->solvers.push_back(WahbaSolver::create(s));
    return w;
  }

  Report summarise(const McOptions& o, const Table& t) const override {
    // per axis, at the image centre
    const double sigma_star_arcsec = rad2arcsec(o.noise_px * makeCamera(o).pixelScale());
    Report rep;
    rep.title = "Attitude error vs number of stars, per Wahba solver";
    rep.notes.push_back(
        "Known correspondences; centroid noise " + fmt(o.noise_px, 3) + " px per axis (" +
        fmt(sigma_star_arcsec, 3) + "\" per axis at the image centre), " + fmt(o.fov_deg, 4) +
        " deg FOV, stars V <= " + fmt(o.mag_limit, 3) + " taken in random order. `rms_cross` is "
        "the RMS angle between true and estimated boresight, `pred_cross` the RMS of the "
        "solver's sqrt(Pxx + Pyy); likewise for roll. Their ratio is 1 when the covariance is "
        "right; `nees` should be 3. `seed003` is seed 003's rule sqrt(2) sigma_star / sqrt(N) "
        "for the cross-boresight error (two axes); `max_total` is seed 000 Fig. 12's maximum "
        "error. N is limited by the stars visible: large N only come from rich fields.");
    const std::size_t c_n = t.col("n_stars"), c_s = t.col("solver"), c_ok = t.col("ok"),
                      c_ec = t.col("err_cross_arcsec"), c_er = t.col("err_roll_arcsec"),
                      c_et = t.col("err_total_arcsec"), c_sc = t.col("sigma_cross_arcsec"),
                      c_sr = t.col("sigma_roll_arcsec"), c_ne = t.col("nees");
    struct Acc {
      std::size_t n = 0, ok = 0;
      std::vector<double> ec, er, et, sc, sr, ne;
    };
    std::map<std::pair<int, std::string>, Acc> acc;
    for (const Row& r : t.rows) {
      if (r[c_s] == "-") continue;
      Acc& a = acc[{static_cast<int>(cellNum(r, c_n)), r[c_s]}];
      ++a.n;
      if (r[c_ok] != "1") continue;
      ++a.ok;
      a.ec.push_back(cellNum(r, c_ec));
      a.er.push_back(cellNum(r, c_er));
      a.et.push_back(cellNum(r, c_et));
      a.sc.push_back(cellNum(r, c_sc));
      a.sr.push_back(cellNum(r, c_sr));
      a.ne.push_back(cellNum(r, c_ne));
    }
    ReportTable tab;
    tab.name = "errors";
    tab.caption = "Attitude error vs number of stars (arcsec)";
    tab.table.columns = {"n_stars", "solver", "trials", "ok", "rms_cross", "pred_cross",
                         "ratio_cross", "rms_roll", "pred_roll", "ratio_roll", "nees",
                         "max_total", "seed003"};
    Plot pc, pr, pn;
    pc.title = "Cross-boresight error vs number of stars (" + fmt(o.noise_px, 3) + " px noise)";
    pr.title = "Roll error vs number of stars (" + fmt(o.noise_px, 3) + " px noise)";
    for (Plot* p : {&pc, &pr}) {
      p->xlabel = "stars used";
      p->ylabel = "RMS error [arcsec]";
      p->log_x = p->log_y = true;
    }
    pn.title = "Mean NEES vs number of stars (3 = consistent covariance)";
    pn.xlabel = "stars used";
    pn.ylabel = "mean NEES";
    pn.log_x = true;
    pn.log_y = true;
    pn.ref_lines.push_back({3.0, "3"});
    // The prediction line: the default solver's covariance when it ran (TRIAD's differs).
    const std::string pred_solver =
        std::count(o.solvers.begin(), o.solvers.end(), WahbaSolver::defaultName())
            ? WahbaSolver::defaultName()
            : o.solvers.front();
    PlotSeries pred_c{"predicted (covariance, " + pred_solver + ")", PlotStyle::Lines},
        pred_r{"predicted (covariance, " + pred_solver + ")", PlotStyle::Lines},
        rule{"seed 003: sqrt(2) sigma_star / sqrt(N)", PlotStyle::Lines};
    pred_c.color = pred_r.color = "#000000";
    rule.color = "#808080";
    rule.dashed = true;
    std::map<std::string, PlotSeries> sc, sr, sn;
    for (const std::string& s : o.solvers) {
      sc[s] = {s, PlotStyle::Points};
      sr[s] = {s, PlotStyle::Points};
      sn[s] = {s, PlotStyle::LinesPoints};
    }
    for (int n : kStarCounts) {
      bool any = false;
      for (const std::string& s : o.solvers) {
        auto it = acc.find({n, s});
        if (it == acc.end()) continue;
        any = true;
        const Acc& a = it->second;
        const double rc = rms(a.ec), pc_ = rms(a.sc), rr = rms(a.er), pr_ = rms(a.sr);
        const double rule_v = std::sqrt(2.0) * sigma_star_arcsec / std::sqrt(double(n));
        tab.table.rows.push_back({std::to_string(n), s, std::to_string(a.n),
                                  std::to_string(a.ok), fmt(rc, 4), fmt(pc_, 4),
                                  fmt(rc / pc_, 3), fmt(rr, 4), fmt(pr_, 4), fmt(rr / pr_, 3),
                                  fmt(mean(a.ne), 4), fmt(quantile(a.et, 1), 4),
                                  fmt(rule_v, 4)});
        sc[s].x.push_back(n);
        sc[s].y.push_back(rc);
        sr[s].x.push_back(n);
        sr[s].y.push_back(rr);
        sn[s].x.push_back(n);
        sn[s].y.push_back(mean(a.ne));
        if (s == pred_solver) {
          pred_c.x.push_back(n);
          pred_c.y.push_back(pc_);
          pred_r.x.push_back(n);
          pred_r.y.push_back(pr_);
        }
      }
      if (any) {
        rule.x.push_back(n);
        rule.y.push_back(std::sqrt(2.0) * sigma_star_arcsec / std::sqrt(double(n)));
      }
    }
    pc.series = {pred_c, rule};
    pr.series = {pred_r};
    for (const std::string& s : o.solvers) {
      pc.series.push_back(sc[s]);
      pr.series.push_back(sr[s]);
      pn.series.push_back(sn[s]);
    }
    rep.tables.push_back(tab);
    rep.plots.push_back({"cross", pc});
    rep.plots.push_back({"roll", pr});
    rep.plots.push_back({"nees", pn});
    return rep;
  }

 private:
  std::shared_ptr<const StarDatabase> db_;
  CameraModel cam_;
};

}  // namespace

std::unique_ptr<Experiment> makeErrorVsStars() { return std::make_unique<ErrorVsStars>(); }

}  // namespace st::app::mc

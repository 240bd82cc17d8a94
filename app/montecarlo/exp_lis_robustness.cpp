// lis-robustness: lost-in-space identification under error situations, per algorithm.
// Seed 003 Tables 2 and 3 (success rate and accuracy per error situation: false star, star
// outside the tolerance limits, star missing), seed 000 (spikes), issue 6 (false stars must
// never produce a wrong attitude reported as a success), plus sweeps in the number of false
// stars, the fraction of dropped stars and the centroid noise.
//
// Every trial is one random attitude; each situation draws its scene from its own sub-stream
// of the trial seed, and every algorithm sees the same scene (paired comparison).
//
// A solved trial is a FALSE ID when its attitude error exceeds
//   max(10 * sigma_total, 1 arcmin),  sigma_total = sqrt(trace(cov_cam)),
// i.e. the reported covariance does not cover the error by a wide margin: a correct solution
// has NEES ~ chi-square(3), so 10 sigma is never reached by chance.
#include <algorithm>
#include <cmath>
#include <map>

#include "app/montecarlo/experiments.hpp"
#include "app/montecarlo/sky.hpp"
#include "app/montecarlo/stats.hpp"
#include "common/conventions.hpp"
#include "common/errors.hpp"
#include "sensors/identify/identifier.hpp"

namespace st::app::mc {
namespace {

constexpr double kFalseIdSigmas = 10.0;
constexpr double kFalseIdFloorArcsec = 60.0;

std::vector<ErrorSituation> situations(double noise) {
  auto S = [noise](std::string name, int n_false, double drop, int missing, int displaced,
                   double noise_mult) {
    ErrorSituation s;
    s.name = std::move(name);
    s.noise_px = noise * noise_mult;
    s.false_stars = n_false;
    s.drop_fraction = drop;
    s.missing = missing;
    s.displaced = displaced;
    return s;
  };
  return {
      // seed 003 Table 2 rows
      S("all stars in tolerance", 0, 0, 0, 0, 1),
      S("1 false star", 1, 0, 0, 0, 1),
      S("1 star outside tolerance", 0, 0, 0, 1, 1),
      S("2 stars outside tolerance", 0, 0, 0, 2, 1),
      S("1 outside tolerance + 1 false", 1, 0, 0, 1, 1),
      S("1 star missing", 0, 0, 1, 0, 1),
      // false-star sweep (seed 000 spikes)
      S("2 false stars", 2, 0, 0, 0, 1),
      S("3 false stars", 3, 0, 0, 0, 1),
      S("5 false stars", 5, 0, 0, 0, 1),
      S("8 false stars", 8, 0, 0, 0, 1),
      S("12 false stars", 12, 0, 0, 0, 1),
      // dropped-star sweep
      S("10% dropped", 0, 0.1, 0, 0, 1),
      S("20% dropped", 0, 0.2, 0, 0, 1),
      S("30% dropped", 0, 0.3, 0, 0, 1),
      S("50% dropped", 0, 0.5, 0, 0, 1),
      // noise sweep
      S("noise x0.5", 0, 0, 0, 0, 0.5),
      S("noise x2", 0, 0, 0, 0, 2),
      S("noise x5", 0, 0, 0, 0, 5),
      S("noise x10", 0, 0, 0, 0, 10),
      // issue 6 style mix
      S("3 false + 10% dropped", 3, 0.1, 0, 0, 1),
  };
}

const ErrorSituation* findSituation(const std::vector<ErrorSituation>& all, const std::string& n) {
  for (const auto& s : all)
    if (s.name == n) return &s;
  return nullptr;
}

class LisRobustness : public Experiment {
 public:
  std::string name() const override { return "lis-robustness"; }

  void configure(McOptions& o) const override {
    if (o.algorithms.empty()) o.algorithms = StarIdentifier::names();
    for (const std::string& a : o.algorithms) {
      std::string err;
      if (!StarIdentifier::create(a, {}, &err)) throw InputError("--algorithms: " + err);
    }
    if (o.noise_px <= 0) throw InputError("--noise-px must be > 0 for lis-robustness");
  }

  std::vector<std::string> columns(const McOptions&) const override {
    return {"trial", "situation", "algorithm", "n_true", "n_false", "status", "matched",
            "solved", "false_id", "wrong_stars", "err_cross_arcsec", "err_roll_arcsec",
            "err_total_arcsec", "sigma_total_arcsec", "nees"};
  }

  void prepare(const McOptions& o) override {
    cam_ = makeCamera(o);
    db_ = buildDatabase(o, 2 * cam_.halfDiagonalFov() + deg2rad(0.5), o.mag_limit);
  }

  std::unique_ptr<TrialWorker> makeWorker(const McOptions& o) const override {
    struct W : TrialWorker {
      const LisRobustness* e;
      McOptions o;
      std::vector<ErrorSituation> sits;
      std::vector<std::unique_ptr<StarIdentifier>> ids;
      void run(uint64_t trial, uint64_t seed, std::vector<Row>& rows) override {
        std::mt19937_64 rng(seed);
        const Quat q = randomAttitude(rng);
        const auto vis = visibleStars(*e->db_, e->cam_, q, o.mag_limit, fieldStop(o));
        for (std::size_t si = 0; si < sits.size(); ++si) {
          std::mt19937_64 srng(trialSeed(seed, trial, si + 1));
          const Scene sc = makeScene(srng, e->cam_, vis, sits[si]);
          const auto obs = toStarObservations(sc.centroids, e->cam_);
          for (const auto& id : ids) {
            const IdentifyResult r = id->identify(obs, *e->db_, e->cam_);
            Row row = {std::to_string(trial), sits[si].name, id->name(),
                       std::to_string(sc.n_true), std::to_string(sc.n_false),
                       toString(r.status), std::to_string(r.matches.size()),
                       r.solved() ? "1" : "0"};
            if (r.solved()) {
              const AttitudeError err = attitudeError(r.q_ic, q);
              const double sigma = std::sqrt(std::max(0.0, r.cov_cam.trace()));
              const bool false_id =
                  err.total > std::max(kFalseIdSigmas * sigma, arcsec2rad(kFalseIdFloorArcsec));
              int wrong = 0;
              for (const StarMatch& m : r.matches)
                wrong += sc.truth[m.obs_index] != static_cast<int>(m.star_index);
              row.insert(row.end(),
                         {false_id ? "1" : "0", std::to_string(wrong),
                          fmt(rad2arcsec(err.cross_boresight), 6), fmt(rad2arcsec(err.roll), 6),
                          fmt(rad2arcsec(err.total), 6), fmt(rad2arcsec(sigma), 6),
                          fmt(attitudeNees(r.q_ic, r.cov_cam, q), 6)});
            } else {
              row.insert(row.end(), {"0", "0", "nan", "nan", "nan", "nan", "nan"});
            }
            rows.push_back(std::move(row));
          }
        }
      }
    };
    auto w = std::make_unique<W>();
    w->e = this;
    w->o = o;
    w->sits = situations(o.noise_px);
    for (const std::string& a : o.algorithms) w->ids.push_back(StarIdentifier::create(a));
    return w;
  }

  Report summarise(const McOptions& o, const Table& t) const override {
    const auto sits = situations(o.noise_px);
    Report rep;
    rep.title = "Lost-in-space robustness per error situation and algorithm";
    rep.notes.push_back(
        "Simulated centroids: database stars V <= " + fmt(o.mag_limit, 3) + " projected through a " +
        std::to_string(o.width) + "x" + std::to_string(o.height) + " px camera with " +
        fmt(o.fov_deg, 4) + " deg horizontal FOV at uniformly random attitudes, Gaussian noise " +
        fmt(o.noise_px, 3) + " px per axis (the reported centroid covariance), then the error "
        "situation: false stars at random pixels and brightness ranks, stars dropped with a "
        "probability, one star removed (\"missing\"), or stars moved by 10 sigma in a random "
        "direction without telling the covariance (\"outside tolerance\", seed 003 Table 2).");
    rep.notes.push_back(
        "`correct` = solved and not a false ID. A solved trial is a **false ID** when its "
        "attitude error exceeds max(10 sigma_total, 60\") with sigma_total = sqrt(trace P) of the "
        "reported covariance. `false_id_ci95_hi` is the upper end of the 95 % Wilson interval "
        "of the false-ID rate (about 3.8/n when none was seen). `wrong_stars` counts matched "
        "observations whose true star differs (false stars included); `rms_cross`/`rms_roll` are "
        "the RMS cross-boresight / roll errors of the correct solutions (seed 003 Table 3), "
        "`nees` their mean normalised error (3 when the covariance is right).");
    const std::size_t c_sit = t.col("situation"), c_alg = t.col("algorithm"),
                      c_solved = t.col("solved"), c_false = t.col("false_id"),
                      c_wrong = t.col("wrong_stars"), c_cross = t.col("err_cross_arcsec"),
                      c_roll = t.col("err_roll_arcsec"), c_nees = t.col("nees"),
                      c_match = t.col("matched"), c_true = t.col("n_true");
    struct Acc {
      std::size_t n = 0, solved = 0, false_id = 0, wrong = 0;
      std::vector<double> cross, roll, nees, matched, n_true;
    };
    std::map<std::pair<std::string, std::string>, Acc> acc;
    for (const Row& r : t.rows) {
      Acc& a = acc[{r[c_sit], r[c_alg]}];
      ++a.n;
      a.n_true.push_back(cellNum(r, c_true));
      if (r[c_solved] != "1") continue;
      ++a.solved;
      a.wrong += static_cast<std::size_t>(cellNum(r, c_wrong));
      if (r[c_false] == "1") {
        ++a.false_id;
        continue;
      }
      a.cross.push_back(cellNum(r, c_cross));
      a.roll.push_back(cellNum(r, c_roll));
      a.nees.push_back(cellNum(r, c_nees));
      a.matched.push_back(cellNum(r, c_match));
    }
    ReportTable tab;
    tab.name = "situations";
    tab.caption = "Success rate, false IDs and accuracy per error situation";
    tab.table.columns = {"situation", "algorithm", "trials", "mean_stars", "solved_%",
                         "correct_%", "false_ids", "false_id_ci95_hi", "wrong_stars",
                         "rms_cross_arcsec", "rms_roll_arcsec", "mean_matched", "nees"};
    auto pct = [](std::size_t k, std::size_t n) { return n ? fmt(100.0 * double(k) / double(n), 5) : "nan"; };
    for (const ErrorSituation& s : sits)
      for (const std::string& alg : o.algorithms) {
        auto it = acc.find({s.name, alg});
        if (it == acc.end()) continue;
        const Acc& a = it->second;
        tab.table.rows.push_back(
            {s.name, alg, std::to_string(a.n), fmt(mean(a.n_true), 4), pct(a.solved, a.n),
             pct(a.solved - a.false_id, a.n), std::to_string(a.false_id),
             fmt(wilson95(a.false_id, a.n).hi, 3), std::to_string(a.wrong), fmt(rms(a.cross), 4),
             fmt(rms(a.roll), 4), fmt(mean(a.matched), 4), fmt(mean(a.nees), 4)});
      }
    rep.tables.push_back(tab);

    // Sweeps: success vs one factor, the others at their baseline.
    struct Sweep {
      std::string name, title, xlabel;
      std::vector<std::pair<std::string, double>> points;  // situation, x
      bool log_x = false;
    };
    const std::vector<Sweep> sweeps = {
        {"vs_false_stars", "Correct identifications vs false stars", "false stars in the image",
         {{"all stars in tolerance", 0}, {"1 false star", 1}, {"2 false stars", 2},
          {"3 false stars", 3}, {"5 false stars", 5}, {"8 false stars", 8},
          {"12 false stars", 12}}},
        {"vs_dropped", "Correct identifications vs dropped stars", "fraction of stars dropped",
         {{"all stars in tolerance", 0}, {"10% dropped", 0.1}, {"20% dropped", 0.2},
          {"30% dropped", 0.3}, {"50% dropped", 0.5}}},
        {"vs_noise", "Correct identifications vs centroid noise", "centroid noise [px, 1 sigma]",
         {{"noise x0.5", 0.5 * o.noise_px}, {"all stars in tolerance", o.noise_px},
          {"noise x2", 2 * o.noise_px}, {"noise x5", 5 * o.noise_px},
          {"noise x10", 10 * o.noise_px}},
         true},
    };
    for (const Sweep& sw : sweeps) {
      Plot p = makePlot(
          sw.title + " (" + fmt(o.fov_deg, 4) + " deg FOV, V <= " + fmt(o.mag_limit, 3) + ")",
          sw.xlabel, "correct identifications [%]");
      p.log_x = sw.log_x;
      p.key = "bottom left";
      for (const std::string& alg : o.algorithms) {
        PlotSeries s{alg, PlotStyle::ErrorBars};
        for (const auto& [sit, x] : sw.points) {
          auto it = acc.find({sit, alg});
          if (it == acc.end() || !findSituation(sits, sit)) continue;
          const Acc& a = it->second;
          const Interval ci = wilson95(a.solved - a.false_id, a.n);
          s.x.push_back(x);
          s.y.push_back(100.0 * double(a.solved - a.false_id) / double(a.n));
          s.y_lo.push_back(100 * ci.lo);
          s.y_hi.push_back(100 * ci.hi);
        }
        p.series.push_back(s);
      }
      rep.plots.push_back({sw.name, p});
    }
    return rep;
  }

 private:
  std::shared_ptr<const StarDatabase> db_;
  CameraModel cam_;
};

}  // namespace

std::unique_ptr<Experiment> makeLisRobustness() { return std::make_unique<LisRobustness>(); }

}  // namespace st::app::mc

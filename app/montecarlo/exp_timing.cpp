// timing: time per frame per stage vs the number of observed stars (seed 000 Fig. 10: time
// vs n; Fig. 11: admissible star pairs vs n, here the candidate attitudes the search
// examined). Two sources per trial, at the same random attitude:
//   "centroids": simulated centroids (noise, 0-3 false stars, 10 % dropped, as in issue 6);
//   "image":     a rendered and exposed image (sensors/sim: eq. 3.4 photometry, PSF, noise),
//                then star detection (sensors/detect), so detection is timed too.
// Stages: detection (image only), pattern search, verification (both inside identify()), and
// one Wahba solve over all matched stars (mean of kSolveRepeats calls: a single call is below
// the clock's useful resolution). Wall-clock times: rows differ between runs and depend on
// the load; run with --threads 1 on an idle machine for numbers worth quoting.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>

#include "app/montecarlo/experiments.hpp"
#include "app/montecarlo/sky.hpp"
#include "app/montecarlo/stats.hpp"
#include "common/conventions.hpp"
#include "common/errors.hpp"
#include "sensors/attitude/wahba.hpp"
#include "sensors/detect/star_detector.hpp"
#include "sensors/identify/identifier.hpp"
#include "sensors/sim/detector.hpp"
#include "sensors/sim/star_renderer.hpp"
#include "sensors/sim/star_source.hpp"

namespace st::app::mc {
namespace {

constexpr int kSolveRepeats = 20;
using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

class Timing : public Experiment {
 public:
  std::string name() const override { return "timing"; }
  bool measuresTime() const override { return true; }
  bool usesFieldStop() const override { return false; }  // the rendered frames fill the image

  void configure(McOptions& o) const override {
    if (o.algorithms.empty()) o.algorithms = {StarIdentifier::defaultName()};
    for (const std::string& a : o.algorithms) {
      std::string err;
      if (!StarIdentifier::create(a, {}, &err)) throw InputError("--algorithms: " + err);
    }
    if (o.solvers.empty()) o.solvers = {WahbaSolver::defaultName()};
    std::string err;
    if (!WahbaSolver::create(o.solvers.front(), &err)) throw InputError("--solvers: " + err);
    if (o.noise_px <= 0) throw InputError("--noise-px must be > 0 for timing");
  }

  std::vector<std::string> columns(const McOptions&) const override {
    return {"trial",      "source",    "algorithm", "n_obs",    "n_true",
            "solved",     "matched",   "detect_ms", "pattern_ms", "verify_ms",
            "identify_ms", "solve_ms", "attitudes_examined", "hypotheses"};
  }

  void prepare(const McOptions& o) override {
    cam_ = makeCamera(o);
    db_ = buildDatabase(o, 2 * cam_.halfDiagonalFov() + deg2rad(0.5), o.mag_limit);
  }

  std::unique_ptr<TrialWorker> makeWorker(const McOptions& o) const override {
    struct W : TrialWorker {
      const Timing* e;
      McOptions o;
      std::vector<std::unique_ptr<StarIdentifier>> ids;
      std::unique_ptr<WahbaSolver> solver;
      std::unique_ptr<DatabaseStarSource> source;
      std::unique_ptr<StarRenderer> renderer;
      std::unique_ptr<Detector> detector;
      DetectorOptions dopts;
      cv::Mat background;

      void identifyRows(uint64_t trial, const char* src, const std::vector<StarObservation>& obs,
                        int n_true, double detect_ms, std::vector<Row>& rows) {
        for (const auto& id : ids) {
          const IdentifyResult r = id->identify(obs, *e->db_, e->cam_);
          double solve_ms = NAN;
          if (r.solved() && r.matches.size() >= 2) {
            std::vector<VectorObservation> vo;
            for (const StarMatch& m : r.matches)
              vo.push_back({obs[m.obs_index].v_cam, e->db_->stars()[m.star_index].u_i,
                            obs[m.obs_index].sigma});
            const auto t0 = Clock::now();
            for (int k = 0; k < kSolveRepeats; ++k) (void)solver->solve(vo);
            solve_ms = msSince(t0) / kSolveRepeats;
          }
          rows.push_back({std::to_string(trial), src, id->name(), std::to_string(obs.size()),
                          std::to_string(n_true), r.solved() ? "1" : "0",
                          std::to_string(r.matches.size()), fmt(detect_ms, 5),
                          fmt(r.timing.pattern_ms, 5), fmt(r.timing.verify_ms, 5),
                          fmt(r.timing.total_ms, 5), fmt(solve_ms, 5),
                          fmt(r.attitudes_examined, 7), std::to_string(r.hypotheses_tried)});
        }
      }

      void run(uint64_t trial, uint64_t seed, std::vector<Row>& rows) override {
        std::mt19937_64 rng(seed);
        const Quat q = randomAttitude(rng);
        const auto vis = visibleStars(*e->db_, e->cam_, q, o.mag_limit, 0);
        ErrorSituation sit;
        sit.noise_px = o.noise_px;
        sit.false_stars = std::uniform_int_distribution<int>(0, 3)(rng);
        sit.drop_fraction = 0.1;
        const Scene sc = makeScene(rng, e->cam_, vis, sit);
        identifyRows(trial, "centroids", toStarObservations(sc.centroids, e->cam_), sc.n_true,
                     NAN, rows);

        cv::Mat electrons = background.clone();
        const auto truth = renderer->render(constantRateAttitude(q, Vec3::Zero()), electrons);
        const cv::Mat image = detector->expose(electrons, rng);
        const auto t0 = Clock::now();
        const DetectionResult det = detectStars(image, dopts);
        const double detect_ms = msSince(t0);
        identifyRows(trial, "image", toStarObservations(det.stars, e->cam_),
                     static_cast<int>(truth.size()), detect_ms, rows);
      }
    };
    auto w = std::make_unique<W>();
    w->e = this;
    w->o = o;
    for (const std::string& a : o.algorithms) w->ids.push_back(StarIdentifier::create(a));
    w->solver = WahbaSolver::create(o.solvers.front());
    const SensorParams sensor;  // the simulator's default camera electronics
    w->source = std::make_unique<DatabaseStarSource>(*db_);
    w->renderer = std::make_unique<StarRenderer>(cam_, sensor, *w->source);
    w->detector = std::make_unique<Detector>(sensor, cam_.width(), cam_.height());
    w->background = w->detector->meanBackground();
    w->dopts.gain_e_per_adu = sensor.gain();
    return w;
  }

  Report summarise(const McOptions& o, const Table& t) const override {
    Report rep;
    rep.title = "Time per frame per stage vs number of observed stars";
    rep.notes.push_back(
        "Median wall-clock time per stage [ms] per number of observations n (detected or "
        "simulated centroids, false stars included) on " + fmt(o.fov_deg, 4) + " deg FOV, " +
        std::to_string(o.width) + "x" + std::to_string(o.height) + " px frames, V <= " +
        fmt(o.mag_limit, 3) + ". `pattern` and `verify` are the identifier's own timings "
        "(identify = pattern + verify + bookkeeping), `solve` one " + o.solvers.front() +
        " solve over all matched stars, `detect` the full-frame star detection of the rendered "
        "image. `candidates` is the mean number of candidate attitudes the search examined (the "
        "analogue of seed 000 Fig. 11's admissible star pairs). The plots skip bins with fewer "
        "than 5 frames. Timings "
        "depend on the machine and its load: see the command's --threads 1 advice.");
    const std::size_t c_src = t.col("source"), c_alg = t.col("algorithm"), c_n = t.col("n_obs"),
                      c_sol = t.col("solved"), c_det = t.col("detect_ms"),
                      c_pat = t.col("pattern_ms"), c_ver = t.col("verify_ms"),
                      c_id = t.col("identify_ms"), c_slv = t.col("solve_ms"),
                      c_att = t.col("attitudes_examined");
    struct Acc {
      std::size_t n = 0, solved = 0;
      std::vector<double> det, pat, ver, id, slv, att;
    };
    std::map<std::tuple<std::string, std::string, int>, Acc> acc;
    std::map<std::pair<std::string, std::string>, Acc> overall;
    for (const Row& r : t.rows) {
      const int n = static_cast<int>(cellNum(r, c_n));
      for (Acc* a : {&acc[{r[c_src], r[c_alg], n}], &overall[{r[c_src], r[c_alg]}]}) {
        ++a->n;
        a->solved += r[c_sol] == "1";
        const double d = cellNum(r, c_det), s = cellNum(r, c_slv);
        if (std::isfinite(d)) a->det.push_back(d);
        if (std::isfinite(s)) a->slv.push_back(s);
        a->pat.push_back(cellNum(r, c_pat));
        a->ver.push_back(cellNum(r, c_ver));
        a->id.push_back(cellNum(r, c_id));
        a->att.push_back(cellNum(r, c_att));
      }
    }
    auto med = [](const std::vector<double>& v) { return fmt(quantile(v, 0.5), 4); };
    ReportTable sum;
    sum.name = "overall";
    sum.caption = "Per source and algorithm (all frames)";
    sum.table.columns = {"source", "algorithm", "frames", "solved_%", "detect_ms_median",
                         "pattern_ms_median", "verify_ms_median", "identify_ms_median",
                         "identify_ms_p95", "solve_ms_median", "candidates_mean"};
    for (const auto& [key, a] : overall)
      sum.table.rows.push_back({key.first, key.second, std::to_string(a.n),
                                fmt(100.0 * double(a.solved) / double(a.n), 5), med(a.det),
                                med(a.pat), med(a.ver), med(a.id), fmt(quantile(a.id, 0.95), 4),
                                med(a.slv), fmt(mean(a.att), 5)});
    rep.tables.push_back(sum);
    ReportTable tab;
    tab.name = "by_stars";
    tab.caption = "Median time per stage [ms] vs number of observations";
    tab.table.columns = {"source", "algorithm", "n_obs", "frames", "solved_%", "detect_ms",
                         "pattern_ms", "verify_ms", "identify_ms", "identify_ms_p95",
                         "solve_ms", "candidates_mean"};
    // Plots: the stages of the first algorithm on rendered images; identify time and
    // candidates per algorithm on simulated centroids (one series each keeps them readable).
    const std::string first = o.algorithms.front();
    std::map<std::string, PlotSeries> stage_series, id_series, cand_series;
    auto point = [](std::map<std::string, PlotSeries>& m, const std::string& title, double x,
                    double y) {
      PlotSeries& s = m[title];
      s.title = title;
      s.style = PlotStyle::LinesPoints;
      s.x.push_back(x);
      s.y.push_back(y);
    };
    for (const auto& [key, a] : acc) {
      const auto& [src, alg, n] = key;
      tab.table.rows.push_back({src, alg, std::to_string(n), std::to_string(a.n),
                                fmt(100.0 * double(a.solved) / double(a.n), 5), med(a.det),
                                med(a.pat), med(a.ver), med(a.id), fmt(quantile(a.id, 0.95), 4),
                                med(a.slv), fmt(mean(a.att), 5)});
      if (a.n < 5) continue;  // too few frames for a stable median in the plots
      if (src == "image" && alg == first) {
        if (!a.det.empty()) point(stage_series, "detect", n, quantile(a.det, 0.5));
        point(stage_series, "pattern search", n, quantile(a.pat, 0.5));
        point(stage_series, "verification", n, quantile(a.ver, 0.5));
        if (!a.slv.empty()) point(stage_series, "solve (" + o.solvers.front() + ")", n, quantile(a.slv, 0.5));
      }
      if (src == "centroids") {
        point(id_series, alg, n, quantile(a.id, 0.5));
        point(cand_series, alg, n, mean(a.att));
      }
    }
    rep.tables.push_back(tab);
    // Times and counts span decades: log y, one series per stage or algorithm.
    auto logPlot = [](std::string title, std::string xlabel, std::string ylabel,
                      std::string key, const std::map<std::string, PlotSeries>& series) {
      Plot p = makePlot(std::move(title), std::move(xlabel), std::move(ylabel));
      p.log_y = true;
      p.key = std::move(key);
      for (const auto& [k, s] : series) p.series.push_back(s);
      return p;
    };
    const std::string n_obs = "observations (false stars included)";
    rep.plots.push_back(
        {"stages", logPlot("Median time per stage, " + first + ", rendered " +
                               fmt(o.fov_deg, 4) + " deg frames",
                           "detected stars in the frame", "time [ms]", "bottom right",
                           stage_series)});
    rep.plots.push_back(
        {"identify",
         logPlot("Median identification time (pattern + verification), simulated centroids",
                 n_obs, "time [ms]", "top left", id_series)});
    rep.plots.push_back(
        {"candidates", logPlot("Candidate attitudes examined vs observations, simulated "
                               "centroids",
                               n_obs, "mean candidates examined", "top left", cand_series)});
    return rep;
  }

 private:
  std::shared_ptr<const StarDatabase> db_;
  CameraModel cam_;
};

}  // namespace

std::unique_ptr<Experiment> makeTiming() { return std::make_unique<Timing>(); }

}  // namespace st::app::mc

// few-stars: lost-in-space in seed 000's camera (32 deg, V <= 3, 1" centroids) with and
// without the magnitude tie-break (sensors/identify/few_stars.hpp, issue 17 item 4): the
// solved fraction against the fraction of attitudes that show >= 3 stars (72 % in the issue)
// and >= 4 stars (50.6 %), and the wrong attitudes, which must be zero.
//
// Each trial: one uniformly random attitude; every database star V <= mag_limit in the image
// becomes a centroid with Gaussian noise noise_px (also its covariance) and a brightness
// 10^(-0.4 (V + e)), e ~ N(0, kPhotSigma) (the scatter measured on the real tetra3 frames,
// tests/identify/test_photometry.cpp); observations brightest first. Both identifiers are
// Pyramid with false_match_threshold kThreshold; "tie-break" adds magnitude_sigma =
// kPhotSigma. A solved trial is WRONG when a matched star is not the true one or the
// attitude error exceeds max(10 sigma_total, 60") (lis-robustness's false-ID rule).
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

constexpr double kPhotSigma = 0.13;  ///< [mag] photometric 1-sigma (real frames: 0.10-0.18)
constexpr double kThreshold = 1e-6;  ///< false-match threshold: <= 0.01 wrong in 1e4 trials
constexpr double kPaperAtLeast3 = 0.72;    ///< issue 17 item 4 (seed 000 Fig. 1)
constexpr double kPaperAtLeast4 = 0.506;   ///< issue 17, seed 000's camera

class FewStars : public Experiment {
 public:
  std::string name() const override { return "few-stars"; }

  void configure(McOptions& o) const override {
    if (!(o.noise_px > 0)) throw InputError("--noise-px must be > 0 for few-stars");
  }

  std::vector<std::string> columns(const McOptions&) const override {
    return {"trial",     "n_stars", "solved_off", "wrong_off",         "solved_on",
            "wrong_on",  "status_on", "ambiguous_on", "p_false_on", "err_arcsec_on"};
  }

  void prepare(const McOptions& o) override {
    cam_ = makeCamera(o);
    db_ = buildDatabase(o, 2 * cam_.halfDiagonalFov() + deg2rad(0.5), o.mag_limit);
  }

  std::unique_ptr<TrialWorker> makeWorker(const McOptions& o) const override {
    struct W : TrialWorker {
      const FewStars* e;
      McOptions o;
      std::unique_ptr<StarIdentifier> off, on;
      void run(uint64_t trial, uint64_t seed, std::vector<Row>& rows) override {
        std::mt19937_64 rng(seed);
        std::normal_distribution<double> n01;
        const Quat q = randomAttitude(rng);
        const auto vis = visibleStars(*e->db_, e->cam_, q, o.mag_limit, fieldStop(o));
        struct Item {
          double m;
          Centroid c;
          uint32_t star;
        };
        std::vector<Item> items;
        for (const VisibleStar& v : vis) {
          Centroid c{};
          c.px = v.px + o.noise_px * Vec2(n01(rng), n01(rng));
          c.cov_px = o.noise_px * o.noise_px * Mat2::Identity();
          const double m = v.mag + kPhotSigma * n01(rng);
          c.flux = 1e6 * std::pow(10.0, -0.4 * m);
          items.push_back({m, c, v.star});
        }
        std::stable_sort(items.begin(), items.end(),
                         [](const Item& a, const Item& b) { return a.m < b.m; });
        std::vector<Centroid> cs;
        for (const Item& it : items) cs.push_back(it.c);
        const auto obs = toStarObservations(cs, e->cam_, o.noise_px);
        Row row = {std::to_string(trial), std::to_string(items.size())};
        IdentifyResult r_on;
        for (const StarIdentifier* id : {off.get(), on.get()}) {
          const IdentifyResult r = id->identify(obs, *e->db_, e->cam_);
          bool wrong = false;
          if (r.solved()) {
            for (const StarMatch& m : r.matches) wrong |= items[m.obs_index].star != m.star_index;
            const double sigma = std::sqrt(std::max(0.0, r.cov_cam.trace()));
            wrong |= attitudeError(r.q_ic, q).total > std::max(10 * sigma, arcsec2rad(60.0));
          }
          row.push_back(r.solved() ? "1" : "0");
          row.push_back(wrong ? "1" : "0");
          r_on = r;
        }
        row.push_back(toString(r_on.status));
        row.push_back(r_on.reason.find("ambiguous") != std::string::npos ? "1" : "0");
        row.push_back(fmt(r_on.false_match_probability, 4));
        row.push_back(r_on.solved() ? fmt(rad2arcsec(attitudeError(r_on.q_ic, q).total), 5)
                                    : "nan");
        rows.push_back(std::move(row));
      }
    };
    auto w = std::make_unique<W>();
    w->e = this;
    w->o = o;
    IdentifyOptions base;
    base.verify.false_match_threshold = kThreshold;
    w->off = StarIdentifier::create("pyramid", base);
    IdentifyOptions tb = base;
    tb.magnitude_sigma = kPhotSigma;
    w->on = StarIdentifier::create("pyramid", tb);
    return w;
  }

  Report summarise(const McOptions& o, const Table& t) const override {
    Report rep;
    rep.title =
        "Lost-in-space with two or three stars: the magnitude tie-break (seed 000's camera)";
    rep.notes.push_back(
        "Database stars V <= " + fmt(o.mag_limit, 3) + " through a " + std::to_string(o.width) +
        "x" + std::to_string(o.height) + " px camera of " + fmt(o.fov_deg, 4) +
        " deg horizontal FOV at uniformly random attitudes; centroid noise " + fmt(o.noise_px, 3) +
        " px per axis (the covariance told), brightness with " + fmt(kPhotSigma, 3) +
        " mag Gaussian scatter. Pyramid alone (`off`) needs 4 stars; with the magnitude tie-break "
        "(`on`, magnitude_sigma " + fmt(kPhotSigma, 3) + ") fields of 2-3 stars are identified "
        "from every catalog pattern that fits the geometry, the magnitudes and shows no absent "
        "brighter star; more than one survivor is refused. False-match threshold " +
        fmt(kThreshold, 2) + " for both (at most 0.01 wrong attitudes expected in 10^4 trials).");
    rep.notes.push_back(
        "A solved trial is wrong when a matched star is not the true one or its attitude error "
        "exceeds max(10 sigma_total, 60\"). Intervals are 95 % Wilson intervals.");
    const std::size_t c_n = t.col("n_stars"), c_so = t.col("solved_off"),
                      c_wo = t.col("wrong_off"), c_s = t.col("solved_on"),
                      c_w = t.col("wrong_on"), c_amb = t.col("ambiguous_on");
    struct Acc {
      std::size_t n = 0, off = 0, on = 0, wrong_off = 0, wrong_on = 0, ambiguous = 0;
    };
    std::map<int, Acc> per;
    Acc all;
    std::size_t ge3 = 0, ge4 = 0;
    for (const Row& r : t.rows) {
      const int n = static_cast<int>(cellNum(r, c_n));
      Acc& a = per[std::min(n, 8)];
      for (Acc* x : {&a, &all}) {
        ++x->n;
        x->off += r[c_so] == "1";
        x->on += r[c_s] == "1";
        x->wrong_off += r[c_wo] == "1";
        x->wrong_on += r[c_w] == "1";
        x->ambiguous += r[c_amb] == "1";
      }
      ge3 += n >= 3;
      ge4 += n >= 4;
    }
    const double N = double(std::max<std::size_t>(1, all.n));
    auto pct = [](double x) { return fmt(100 * x, 4); };
    auto ci = [&](std::size_t k) {
      const Interval i = wilson95(k, all.n);
      return pct(i.lo) + " .. " + pct(i.hi);
    };
    ReportTable side;
    side.name = "paper_vs_ours";
    side.caption =
        "Seed 000's camera: paper (issue 17) vs ours, " + std::to_string(all.n) + " trials";
    side.table.columns = {"quantity", "paper", "ours_%", "ours_ci95_%"};
    side.table.rows = {
        {"attitudes with >= 3 stars", pct(kPaperAtLeast3), pct(ge3 / N), ci(ge3)},
        {"attitudes with >= 4 stars", pct(kPaperAtLeast4), pct(ge4 / N), ci(ge4)},
        {"solved by Pyramid alone (needs 4)", "-", pct(all.off / N), ci(all.off)},
        {"solved with the magnitude tie-break", "(>= 3 stars: 72)", pct(all.on / N), ci(all.on)},
        {"wrong attitudes with the tie-break (count)", "0", std::to_string(all.wrong_on),
         "<= " + pct(wilson95(all.wrong_on, all.n).hi)},
        {"wrong attitudes of Pyramid alone (count)", "0", std::to_string(all.wrong_off),
         "<= " + pct(wilson95(all.wrong_off, all.n).hi)},
    };
    rep.tables.push_back(side);
    ReportTable tab;
    tab.name = "per_star_count";
    tab.caption = "Per number of stars in the image (8 = 8 or more)";
    tab.table.columns = {"stars", "trials", "solved_off_%", "solved_on_%", "ambiguous_refused_%",
                         "wrong_off", "wrong_on"};
    for (const auto& [n, a] : per) {
      const double k = double(std::max<std::size_t>(1, a.n));
      tab.table.rows.push_back({std::to_string(n) + (n == 8 ? "+" : ""), std::to_string(a.n),
                                pct(a.off / k), pct(a.on / k), pct(a.ambiguous / k),
                                std::to_string(a.wrong_off), std::to_string(a.wrong_on)});
    }
    rep.tables.push_back(tab);
    return rep;
  }

 private:
  std::shared_ptr<const StarDatabase> db_;
  CameraModel cam_;
};

}  // namespace

std::unique_ptr<Experiment> makeFewStars() { return std::make_unique<FewStars>(); }

}  // namespace st::app::mc

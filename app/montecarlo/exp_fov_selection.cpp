// fov-selection: the probability of seeing fewer than 3 or 4 stars vs the size of a square
// FOV, per magnitude limit, and the smallest FOV meeting seed 002 eq. (14):
//   P(No. of stars < 3) < 0.01,  P(No. of stars < 4) < 0.01.
// One trial = one random attitude; every (FOV, magnitude) pair is evaluated on it (common
// random numbers, so the curves are smooth in the FOV).
#include <algorithm>
#include <cmath>

#include "app/montecarlo/experiments.hpp"
#include "app/montecarlo/sky.hpp"
#include "app/montecarlo/stats.hpp"
#include "common/conventions.hpp"
#include "common/errors.hpp"

namespace st::app::mc {
namespace {

std::string fovColumn(double f) { return "n_fov" + fmt(f, 5); }

constexpr double kThreshold = 0.01;  // seed 002 eq. (14)

// R_body_cam of head h: head 0 looks along body +z, head 1 along +x (pitch 90 deg, as
// rawlogs/two_heads.ini), head 2 along +y; mutually perpendicular, so with FOVs under
// 90 deg no star is counted twice.
Mat3 headRotation(int h) {
  Mat3 R;
  if (h == 0) return Mat3::Identity();
  if (h == 1)
    R << 0, 0, 1, 0, 1, 0, -1, 0, 0;  // camera +z -> body +x
  else
    R << 1, 0, 0, 0, 0, 1, 0, -1, 0;  // camera +z -> body +y
  return R;
}

class FovSelection : public Experiment {
 public:
  std::string name() const override { return "fov-selection"; }
  bool usesFieldStop() const override { return false; }
  bool usesHeads() const override { return true; }

  void configure(McOptions& o) const override {
    if (o.fovs_deg.empty())
      for (int f = 4; f <= 40; ++f) o.fovs_deg.push_back(f);
    std::sort(o.fovs_deg.begin(), o.fovs_deg.end());
    o.fovs_deg.erase(std::unique(o.fovs_deg.begin(), o.fovs_deg.end()), o.fovs_deg.end());
    if (o.fovs_deg.front() <= 0 || o.fovs_deg.back() >= 90)
      throw InputError("--fovs: square FOV sizes must be in (0, 90) deg");
    std::sort(o.mags.begin(), o.mags.end());
    o.mags.erase(std::unique(o.mags.begin(), o.mags.end()), o.mags.end());
    if (o.mags.empty()) throw InputError("--mags: give at least one magnitude limit");
    if (o.heads > 1 && o.fovs_deg.back() >= 90)
      throw InputError(
          "--fovs: with --heads the square FOVs must stay under 90 deg (the heads "
          "are 90 deg apart)");
  }

  std::vector<std::string> columns(const McOptions& o) const override {
    std::vector<std::string> c = {"trial", "V_limit"};
    if (o.heads > 1) c.push_back("heads");  // rows for the first head alone and for all
    for (double f : o.fovs_deg) c.push_back(fovColumn(f));
    return c;
  }

  void prepare(const McOptions& o) override { db_ = buildDatabase(o, deg2rad(1.0), o.mags.back()); }

  std::unique_ptr<TrialWorker> makeWorker(const McOptions& o) const override {
    struct W : TrialWorker {
      const FovSelection* e;
      McOptions o;
      std::vector<uint32_t> cone;
      void run(uint64_t trial, uint64_t seed, std::vector<Row>& rows) override {
        std::mt19937_64 rng(seed);
        const Quat q = randomAttitude(rng);
        const Mat3 R_ib = q.toRotationMatrix();
        // Square FOV of full angle f: |x/z| <= tan(f/2) and |y/z| <= tan(f/2), per head.
        const double t_max = std::tan(deg2rad(o.fovs_deg.back()) / 2);
        std::vector<std::pair<double, double>> stars;  // (max |tan|, mag), all heads
        std::size_t first_head = 0;                    // stars[0, first_head) are the first head's
        for (int h = 0; h < o.heads; ++h) {
          if (h == 1) first_head = stars.size();
          const Mat3 R_ic = R_ib * headRotation(h);
          e->db_->coneQuery(R_ic.col(2), std::atan(std::sqrt(2.0) * t_max) + 1e-9, cone);
          for (uint32_t s : cone) {
            const Vec3 v = R_ic.transpose() * e->db_->stars()[s].u_i;
            if (v.z() <= 0) continue;
            stars.push_back(
                {std::max(std::fabs(v.x()), std::fabs(v.y())) / v.z(), e->db_->stars()[s].mag});
          }
        }
        if (o.heads == 1) first_head = stars.size();
        for (int heads : o.heads > 1 ? std::vector<int>{1, o.heads} : std::vector<int>{1}) {
          const auto end = heads == 1 ? stars.begin() + first_head : stars.end();
          for (double m : o.mags) {
            Row r = {std::to_string(trial), fmt(m, 4)};
            if (o.heads > 1) r.push_back(std::to_string(heads));
            for (double f : o.fovs_deg) {
              const double t = std::tan(deg2rad(f) / 2);
              r.push_back(std::to_string(std::count_if(
                  stars.begin(), end, [&](auto& s) { return s.first <= t && s.second <= m; })));
            }
            rows.push_back(std::move(r));
          }
        }
      }
    };
    auto w = std::make_unique<W>();
    w->e = this;
    w->o = o;
    return w;
  }

  Report summarise(const McOptions& o, const Table& t) const override {
    Report rep;
    rep.title = "FOV size selection: P(stars < 3) and P(stars < 4) vs square FOV" +
                (o.heads > 1 ? ", " + std::to_string(o.heads) + " identical heads 90 deg apart"
                             : std::string());
    rep.notes.push_back(
        "Seed 002 §IV eq. (14): for each magnitude limit the smallest square FOV with "
        "P(N < 3) < 0.01 and with P(N < 4) < 0.01, from random attitudes on the real catalog "
        "(double stars closer than " + fmt(o.merge_arcsec, 3) + "\" merged); with several "
        "heads N is the sum over the heads, and each table has the first head alone beside "
        "them (`heads` = 1). `ci95_hi` is the upper end of the 95 % Wilson interval of the "
        "estimated probability: with few trials a FOV can meet 0.01 by luck, and the column "
        "shows how sure the estimate is.");
    const std::size_t c_mag = t.col("V_limit");
    const bool several = o.heads > 1;
    const std::size_t c_heads = several ? t.col("heads") : 0;
    const std::vector<int> head_counts =
        several ? std::vector<int>{1, o.heads} : std::vector<int>{1};
    auto withHeads = [&](std::vector<std::string> cols) {
      if (several) cols.insert(cols.begin(), "heads");
      return cols;
    };
    ReportTable prob;
    prob.name = "probabilities";
    prob.caption = "Probability of fewer than 3 / 4 stars per FOV and magnitude limit";
    prob.table.columns = withHeads({"V_limit", "fov_deg", "trials", "mean_N", "P(N<3)",
                                    "P(N<3)_ci95_hi", "P(N<4)", "P(N<4)_ci95_hi"});
    ReportTable need;
    need.name = "fov_needed";
    need.caption = "Smallest FOV [deg] meeting seed 002 eq. (14)";
    need.table.columns = withHeads({"V_limit", "fov_for_P(N<3)<0.01", "fov_for_P(N<4)<0.01"});
    Plot p3, p4, pn;
    for (Plot* p : {&p3, &p4}) {
      p->xlabel = "square FOV [deg]";
      p->log_y = true;
      p->y_min = 0.5 / std::max<double>(1.0, double(o.runs));
      p->y_max = 1.0;
      p->ref_lines.push_back({kThreshold, "0.01 (eq. 14)"});
    }
    p3.title = "P(fewer than 3 stars) vs FOV";
    p3.ylabel = "P(N < 3)";
    p4.title = "P(fewer than 4 stars) vs FOV";
    p4.ylabel = "P(N < 4)";
    pn.title = "Smallest square FOV with P < 0.01 (seed 002 Fig. 11)";
    pn.xlabel = "magnitude limit V";
    pn.ylabel = "FOV [deg]";
    for (int hv : head_counts) {
      const std::string hs = std::to_string(hv);
      const std::string label = several ? (hv == 1 ? "1 head, " : hs + " heads, ") : "";
      PlotSeries n3{label + "P(N < 3) < 0.01", PlotStyle::LinesPoints},
          n4{label + "P(N < 4) < 0.01", PlotStyle::LinesPoints};
      for (double m : o.mags) {
        const std::string ms = fmt(m, 4);
        PlotSeries s3{label + "V <= " + ms, PlotStyle::LinesPoints},
            s4{label + "V <= " + ms, PlotStyle::LinesPoints};
        double need3 = NAN, need4 = NAN;
        for (double f : o.fovs_deg) {
          const std::size_t c = t.col(fovColumn(f));
          std::size_t n = 0, lt3 = 0, lt4 = 0;
          double sum = 0;
          for (const Row& r : t.rows) {
            if (r[c_mag] != ms || (several && r[c_heads] != hs)) continue;
            const double v = cellNum(r, c, t.columns[c]);
            ++n;
            sum += v;
            lt3 += v < 3;
            lt4 += v < 4;
          }
          if (n == 0) continue;
          const double P3 = double(lt3) / double(n), P4 = double(lt4) / double(n);
          Row pr = {ms,
                    fmt(f, 5),
                    std::to_string(n),
                    fmt(sum / double(n), 4),
                    fmt(P3, 4),
                    fmt(wilson95(lt3, n).hi, 3),
                    fmt(P4, 4),
                    fmt(wilson95(lt4, n).hi, 3)};
          if (several) pr.insert(pr.begin(), hs);
          prob.table.rows.push_back(pr);
          s3.x.push_back(f);
          s3.y.push_back(P3);
          s4.x.push_back(f);
          s4.y.push_back(P4);
          if (std::isnan(need3) && P3 < kThreshold) need3 = f;
          if (std::isnan(need4) && P4 < kThreshold) need4 = f;
        }
        Row nr = {ms, std::isnan(need3) ? "> grid" : fmt(need3, 5),
                  std::isnan(need4) ? "> grid" : fmt(need4, 5)};
        if (several) nr.insert(nr.begin(), hs);
        need.table.rows.push_back(nr);
        n3.x.push_back(m);
        n3.y.push_back(need3);
        n4.x.push_back(m);
        n4.y.push_back(need4);
        p3.series.push_back(s3);
        p4.series.push_back(s4);
      }
      pn.series.push_back(n3);
      pn.series.push_back(n4);
    }
    rep.tables.push_back(need);
    rep.tables.push_back(prob);
    rep.plots.push_back({"p_lt3", p3});
    rep.plots.push_back({"p_lt4", p4});
    rep.plots.push_back({"fov_needed", pn});
    return rep;
  }

 private:
  std::shared_ptr<const StarDatabase> db_;
};

}  // namespace

std::unique_ptr<Experiment> makeFovSelection() { return std::make_unique<FovSelection>(); }

}  // namespace st::app::mc

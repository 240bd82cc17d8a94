#include "navigation/nav_step.hpp"

#include <Eigen/Cholesky>
#include <fstream>
#include <sstream>

#include "common/conventions.hpp"
#include "common/errors.hpp"

namespace st {

void fillFilterState(NavStep& s, const FilterState& f) {
  s.initialized = f.initialized;
  if (!f.initialized) return;
  s.q_ib = canonical(f.q_ib);
  s.bias = f.bias;
  s.P_att = f.attitudeCov();
  s.sigma_att = s.P_att.diagonal().cwiseMax(0.0).cwiseSqrt();
  s.sigma_bias = f.P.bottomRightCorner<3, 3>().diagonal().cwiseMax(0.0).cwiseSqrt();
  s.gyroless = f.gyroless;
  s.rate = f.rate;
  if (f.gyroless) {
    s.P_rate = f.P.bottomRightCorner<3, 3>();
    s.sigma_rate = s.sigma_bias;
    s.sigma_bias.setZero();
  }
}

namespace {

/// The true rate at `s` from its neighbours with truth `a` (before) and `b` (after).
void setTruthRate(const NavStep& a, NavStep& s, const NavStep& b, double max_gap_s) {
  const double dt = b.t - a.t;
  if (!(dt > 0) || b.t - s.t > max_gap_s || s.t - a.t > max_gap_s) return;
  s.has_true_rate = true;
  s.rate_true = quatLog(canonical(a.q_true.conjugate() * b.q_true)) / dt;
  if (!s.initialized) return;
  s.rate_error = s.rate - s.rate_true;
  if (s.gyroless) {
    const Eigen::LDLT<Mat3> ldlt(s.P_rate);
    if (ldlt.info() == Eigen::Success) s.rate_nees = s.rate_error.dot(ldlt.solve(s.rate_error));
  }
}

}  // namespace

void TruthRateStream::push(NavStep s, const Sink& out) {
  if (!s.has_truth) {
    if (held_.empty()) {
      out(s);
    } else {
      held_.push_back(std::move(s));
    }
    return;
  }
  if (!held_.empty()) {
    if (prev_truth_) setTruthRate(*prev_truth_, held_.front(), s, max_gap_s_);
    prev_truth_ = held_.front();
    for (const NavStep& h : held_) out(h);
    held_.clear();
  }
  held_.push_back(std::move(s));
}

void TruthRateStream::flush(const Sink& out) {
  for (const NavStep& h : held_) out(h);
  held_.clear();
}

std::string navStepCsvHeader() {
  return "t_s,has_frame,mode,stars,frame_ms,initialized,reinit,qw,qx,qy,qz,"
         "bias_x_deg_h,bias_y_deg_h,bias_z_deg_h,sigma_x_arcsec,sigma_y_arcsec,sigma_z_arcsec,"
         "sigma_bias_x_deg_h,sigma_bias_y_deg_h,sigma_bias_z_deg_h,update,"
         "innov_x_arcsec,innov_y_arcsec,innov_z_arcsec,innov_sigma_x_arcsec,"
         "innov_sigma_y_arcsec,innov_sigma_z_arcsec,nis,nis_dof,has_truth,err_arcsec,"
         "err_cross_arcsec,err_roll_arcsec,nees,fix_err_arcsec,sigma_cross_arcsec,"
         "sigma_roll_arcsec,fix_nees,misidentified,blend_claims,"
         "fix,fix_qw,fix_qx,fix_qy,fix_qz,fix_sigma_cross_arcsec,fix_sigma_roll_arcsec,"
         "fix_err_cross_arcsec,fix_err_roll_arcsec,"
         "rate_x_deg_s,rate_y_deg_s,rate_z_deg_s,sigma_rate_x_deg_s,sigma_rate_y_deg_s,"
         "sigma_rate_z_deg_s,fix_rate_x_deg_s,fix_rate_y_deg_s,fix_rate_z_deg_s,"
         "true_rate_x_deg_s,true_rate_y_deg_s,true_rate_z_deg_s,rate_err_deg_s,rate_nees,"
         "heads,heads_with_fix,heads_merged,heads_chi2";
}

std::string navStepCsvRow(const NavStep& s) {
  const double deg_h = kDegPerRad * 3600.0;
  // An absent value is "nan" (not 0, which reads as a perfect estimate): the filter's columns
  // before the filter holds a state or in a run without a filter, the raw fix's without a fix.
  const bool filt = s.initialized, fix = s.fix, fix_truth = s.fix && s.has_truth;
  std::ostringstream o;
  o.precision(10);
  const auto put = [&o](bool present, double v) {
    o << ',';
    if (present) {
      o << v;
    } else {
      o << "nan";
    }
  };
  o << s.t << ',' << int(s.has_frame) << ','
    << (s.has_frame ? toString(s.mode) : "no-frame") << ',' << s.stars_matched << ','
    << s.frame_time_s * 1e3 << ',' << int(s.initialized) << ',' << int(s.reinitialized);
  const Quat q = canonical(s.q_ib);
  for (double c : {q.w(), q.x(), q.y(), q.z()}) put(filt, c);
  for (int i = 0; i < 3; ++i) put(filt, s.bias[i] * deg_h);
  for (int i = 0; i < 3; ++i) put(filt, rad2arcsec(s.sigma_att[i]));
  for (int i = 0; i < 3; ++i) put(filt, s.sigma_bias[i] * deg_h);
  o << ',' << toString(s.use);
  for (int i = 0; i < 3; ++i)
    o << ',' << (s.innovation.size() > i ? rad2arcsec(s.innovation[i]) : 0.0);
  for (int i = 0; i < 3; ++i) {
    o << ','
      << (s.innovation_cov.rows() > i ? rad2arcsec(std::sqrt(s.innovation_cov(i, i))) : 0.0);
  }
  o << ',' << s.nis << ',' << s.nis_dof << ',' << int(s.has_truth);
  put(filt, rad2arcsec(s.error.total));
  put(filt, rad2arcsec(s.error.cross_boresight));
  put(filt, rad2arcsec(s.error.roll));
  put(filt, s.nees);
  put(fix_truth, rad2arcsec(s.fix_error.total));
  const AttitudeSigma sg = attitudeSigma(s.P_att);
  put(filt, rad2arcsec(sg.cross_boresight));
  put(filt, rad2arcsec(sg.roll));
  put(fix_truth, s.fix_nees);
  o << ',' << s.misidentified << ',' << s.blend_claims;
  // The raw fix itself: the output of a run without a filter.
  o << ',' << int(fix);
  const Quat qf = canonical(s.q_fix);
  for (double c : {qf.w(), qf.x(), qf.y(), qf.z()}) put(fix, c);
  const AttitudeSigma sf = attitudeSigma(s.cov_fix);
  put(fix, rad2arcsec(sf.cross_boresight));
  put(fix, rad2arcsec(sf.roll));
  put(fix_truth, rad2arcsec(s.fix_error.cross_boresight));
  put(fix_truth, rad2arcsec(s.fix_error.roll));
  // Rates: the filter's (gyroless: the state, with its sigma; gyro: the gyro minus the bias),
  // the tracker's own frame-to-frame one, the truth's and the filter's error against it.
  for (int i = 0; i < 3; ++i) put(filt, s.rate[i] * kDegPerRad);
  for (int i = 0; i < 3; ++i) put(filt && s.gyroless, s.sigma_rate[i] * kDegPerRad);
  for (int i = 0; i < 3; ++i) put(s.has_fix_rate, s.fix_rate[i] * kDegPerRad);
  for (int i = 0; i < 3; ++i) put(s.has_true_rate, s.rate_true[i] * kDegPerRad);
  put(filt && s.has_true_rate, s.rate_error.norm() * kDegPerRad);
  put(filt && s.gyroless && s.has_true_rate, s.rate_nees);
  // Several heads: how many had a fix, whether they were merged, their disagreement.
  int with_fix = 0;
  for (const NavHead& h : s.heads) with_fix += h.fix;
  o << ',' << s.heads.size() << ',' << with_fix << ',' << int(s.heads_merged);
  put(s.heads_dof > 0, s.heads_chi2);
  return o.str();
}

NavStepCsvWriter::NavStepCsvWriter(const std::string& path)
    : path_(path), out_(path), f_(out_.tempPath()) {
  if (!f_) throw InputError(path + ": cannot write the CSV");
  f_ << navStepCsvHeader() << '\n';
}

void NavStepCsvWriter::write(const NavStep& s) {
  if (!s.has_frame) return;
  f_ << navStepCsvRow(s) << '\n';
  ++rows_;
}

int NavStepCsvWriter::finish() {
  if (!f_.is_open()) return rows_;  // finished already
  f_.close();
  if (!f_) throw InputError(path_ + ": write failed");
  out_.commit();
  return rows_;
}

}  // namespace st

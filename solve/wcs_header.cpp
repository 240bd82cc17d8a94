#include "common/output_file.hpp"
#include "solve/wcs_header.hpp"

#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <vector>

#include "common/conventions.hpp"
#include "common/errors.hpp"

namespace st::solve {
namespace {

constexpr int kGrid = 41;
constexpr int kSipOrder = 5;

struct Term {
  int p, q;
};

std::vector<Term> terms(int order) {
  std::vector<Term> t;
  for (int n = 1; n <= order; ++n)
    for (int p = n; p >= 0; --p) t.push_back({p, n - p});
  return t;
}

/// Least squares of values(k) = sum_j c_j u^p v^q over the points, in scaled variables for
/// conditioning; returns the unscaled coefficients.
Eigen::VectorXd fitPolynomial(const std::vector<Vec2>& uv, const Eigen::VectorXd& values,
                              const std::vector<Term>& t, double scale) {
  Eigen::MatrixXd m(Eigen::Index(uv.size()), Eigen::Index(t.size()));
  for (std::size_t k = 0; k < uv.size(); ++k)
    for (std::size_t j = 0; j < t.size(); ++j)
      m(Eigen::Index(k), Eigen::Index(j)) =
          std::pow(uv[k].x() / scale, t[j].p) * std::pow(uv[k].y() / scale, t[j].q);
  Eigen::VectorXd c = m.colPivHouseholderQr().solve(values);
  for (std::size_t j = 0; j < t.size(); ++j) c(Eigen::Index(j)) /= std::pow(scale, t[j].p + t[j].q);
  return c;
}

double evalPolynomial(const Eigen::VectorXd& c, const std::vector<Term>& t, const Vec2& uv,
                      int min_degree) {
  double s = 0;
  for (std::size_t j = 0; j < t.size(); ++j)
    if (t[j].p + t[j].q >= min_degree)
      s += c(Eigen::Index(j)) * std::pow(uv.x(), t[j].p) * std::pow(uv.y(), t[j].q);
  return s;
}

class Cards {
 public:
  void add(const std::string& key, const std::string& value, const std::string& comment = "") {
    char b[96];
    std::snprintf(b, sizeof b, "%-8.8s= %20s%s%s", key.c_str(), value.c_str(),
                  comment.empty() ? "" : " / ", comment.c_str());
    push(b);
  }
  void num(const std::string& key, double v, const std::string& comment = "") {
    char b[40];
    std::snprintf(b, sizeof b, "%.15G", v);
    std::string s = b;
    if (s.find_first_of(".E") == std::string::npos) s += ".0";  // a real, not an integer
    add(key, s, comment);
  }
  void integer(const std::string& key, long v, const std::string& comment = "") {
    add(key, std::to_string(v), comment);
  }
  void str(const std::string& key, const std::string& v, const std::string& comment = "") {
    std::string quoted = "'" + v + std::string(v.size() < 8 ? 8 - v.size() : 0, ' ') + "'";
    quoted.resize(std::max<std::size_t>(quoted.size(), 20), ' ');
    std::string k = key.substr(0, 8);
    k.resize(8, ' ');
    push(k + "= " + quoted + (comment.empty() ? "" : " / " + comment));
  }
  void comment(const std::string& text) { push("COMMENT " + text); }
  std::string text() const {
    std::string out = text_ + pad("END");
    out.append((2880 - out.size() % 2880) % 2880, ' ');
    return out;
  }

 private:
  static std::string pad(std::string s) {
    s.resize(80, ' ');
    return s;
  }
  void push(const std::string& s) { text_ += pad(s); }
  std::string text_;
};

}  // namespace

void writeWcsHeader(const SolveReport& r, const std::string& path) {
  IdentifyResult res = r.ps.search.result;
  CelestialFrame astrometric;
  astrometric.annual = false;
  changeFrame(res, r.db, r.frame, r.epoch.jyear, astrometric, r.epoch.jyear);
  const CameraModel& cam = r.ps.search.camera;
  const bool flipped = r.ps.parity == Parity::Flipped;
  const int w = r.in.width, h = r.in.height;
  const Mat3 rot = res.q_ic.toRotationMatrix();
  // The principal point in the input's pixels (a flipped image is mirrored: x -> w - 1 - x).
  const Vec2 pp(flipped ? w - 1 - cam.cx() : cam.cx(), cam.cy());
  const Vec3 b = rot.col(2);
  const double ra0 = std::atan2(b.y(), b.x()), dec0 = std::asin(std::clamp(b.z(), -1.0, 1.0));
  const Vec3 east(-std::sin(ra0), std::cos(ra0), 0);
  const Vec3 north(-std::sin(dec0) * std::cos(ra0), -std::sin(dec0) * std::sin(ra0), std::cos(dec0));

  std::vector<Vec2> offsets;
  Eigen::VectorXd xi(kGrid * kGrid), eta(kGrid * kGrid);
  for (int i = 0; i < kGrid; ++i)
    for (int j = 0; j < kGrid; ++j) {
      const Vec2 px(-0.5 + w * double(i) / (kGrid - 1), -0.5 + h * double(j) / (kGrid - 1));
      const Vec3 d = rot * cam.pixelToVector(Vec2(flipped ? w - 1 - px.x() : px.x(), px.y()));
      const Eigen::Index k = Eigen::Index(offsets.size());
      xi(k) = rad2deg(d.dot(east) / d.dot(b));
      eta(k) = rad2deg(d.dot(north) / d.dot(b));
      offsets.push_back(px - pp);
    }
  const bool sip = !cam.distortion().isZero();
  const std::vector<Term> t = terms(sip ? kSipOrder : 1);
  const double scale = std::max(w, h) / 2.0;
  const Eigen::VectorXd cx = fitPolynomial(offsets, xi, t, scale);
  const Eigen::VectorXd cy = fitPolynomial(offsets, eta, t, scale);
  Eigen::Matrix2d cd;
  cd << cx(0), cx(1), cy(0), cy(1);  // terms(): (1,0) then (0,1)
  const Eigen::Matrix2d cd_inv = cd.inverse();

  // Forward SIP terms: CD (u + A) = the fitted polynomial, so A = CD^-1 (degree >= 2 part).
  Eigen::VectorXd a = Eigen::VectorXd::Zero(Eigen::Index(t.size())), bb = a;
  for (std::size_t j = 2; j < t.size(); ++j) {
    const Eigen::Vector2d s = cd_inv * Eigen::Vector2d(cx(Eigen::Index(j)), cy(Eigen::Index(j)));
    a(Eigen::Index(j)) = s.x();
    bb(Eigen::Index(j)) = s.y();
  }
  // Inverse terms: u = U + AP(U, V) with (U, V) = CD^-1 (xi, eta).
  std::vector<Vec2> uv_lin;
  Eigen::VectorXd du(kGrid * kGrid), dv(kGrid * kGrid);
  for (std::size_t k = 0; k < offsets.size(); ++k) {
    const Eigen::Vector2d lin = cd_inv * Eigen::Vector2d(xi(Eigen::Index(k)), eta(Eigen::Index(k)));
    uv_lin.emplace_back(lin.x(), lin.y());
    du(Eigen::Index(k)) = offsets[k].x() - lin.x();
    dv(Eigen::Index(k)) = offsets[k].y() - lin.y();
  }
  const Eigen::VectorXd ap = fitPolynomial(uv_lin, du, t, scale);
  const Eigen::VectorXd bp = fitPolynomial(uv_lin, dv, t, scale);
  // The fit's largest error over the grid, both ways [px].
  double err_fwd = 0, err_inv = 0;
  for (std::size_t k = 0; k < offsets.size(); ++k) {
    const Vec2& o = offsets[k];
    const Eigen::Vector2d u(o.x() + evalPolynomial(a, t, o, 2), o.y() + evalPolynomial(bb, t, o, 2));
    const Eigen::Vector2d sky = cd * u;
    const Eigen::Vector2d truth(xi(Eigen::Index(k)), eta(Eigen::Index(k)));
    err_fwd = std::max(err_fwd, (cd_inv * (sky - truth)).norm());
    const Vec2& l = uv_lin[k];
    const Vec2 back(l.x() + evalPolynomial(ap, t, l, 1), l.y() + evalPolynomial(bp, t, l, 1));
    err_inv = std::max(err_inv, (back - o).norm());
  }

  Cards c;
  c.add("SIMPLE", "T", "a header without data");
  c.integer("BITPIX", 8);
  c.integer("NAXIS", 0);
  c.integer("WCSAXES", 2);
  c.str("CTYPE1", sip ? "RA---TAN-SIP" : "RA---TAN", "gnomonic projection");
  c.str("CTYPE2", sip ? "DEC--TAN-SIP" : "DEC--TAN");
  c.str("RADESYS", "ICRS", "astrometric: catalog directions, no aberration");
  c.num("EQUINOX", 2000.0);
  c.str("CUNIT1", "deg");
  c.str("CUNIT2", "deg");
  double ra0_deg = rad2deg(ra0);
  if (ra0_deg < 0) ra0_deg += 360;
  c.num("CRVAL1", ra0_deg, "RA of the principal point [deg]");
  c.num("CRVAL2", rad2deg(dec0), "Dec of the principal point [deg]");
  c.num("CRPIX1", pp.x() + 1, "principal point, x (1 = first column's centre)");
  c.num("CRPIX2", pp.y() + 1, "principal point, y (1 = first row's centre)");
  c.num("CD1_1", cd(0, 0));
  c.num("CD1_2", cd(0, 1));
  c.num("CD2_1", cd(1, 0));
  c.num("CD2_2", cd(1, 1));
  c.integer("IMAGEW", w);
  c.integer("IMAGEH", h);
  c.num("MJD-OBS", 51544.5 + (r.epoch.jyear - 2000.0) * 365.25, "observation epoch (TT)");
  if (sip) {
    const char* names[4] = {"A", "B", "AP", "BP"};
    const Eigen::VectorXd* coef[4] = {&a, &bb, &ap, &bp};
    for (int n = 0; n < 4; ++n) {
      c.integer(std::string(names[n]) + "_ORDER", kSipOrder);
      for (std::size_t j = n < 2 ? 2 : 0; j < t.size(); ++j)
        c.num(std::string(names[n]) + "_" + std::to_string(t[j].p) + "_" + std::to_string(t[j].q),
              (*coef[n])(Eigen::Index(j)));
    }
  }
  char b1[80];
  std::snprintf(b1, sizeof b1, "fit of the camera model: max error %.2g px (pixel->sky), %.2g px",
                err_fwd, err_inv);
  c.comment(b1);
  c.comment("(sky->pixel) over the image; startracker solve " + r.o.input);
  try {
    writeFileAtomically(path, c.text());
  } catch (const InputError& e) {
    throw InputError(std::string("--wcs ") + e.what());
  }
}

}  // namespace st::solve

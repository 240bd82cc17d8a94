#include "tests/support/wcs_reference.hpp"

#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace st::test {
namespace {
constexpr double kDeg = M_PI / 180;
}

WcsReference::WcsReference(const std::string& path, bool rows_doubled) : rows_doubled_(rows_doubled) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw std::runtime_error(path + ": cannot open");
  std::string text((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  for (std::size_t i = 0; i + 80 <= text.size(); i += 80) {
    const std::string card = text.substr(i, 80);
    if (card.rfind("END", 0) == 0) break;
    if (card.size() < 10 || card[8] != '=') continue;
    std::string name = card.substr(0, 8);
    name.erase(name.find_last_not_of(' ') + 1);
    std::istringstream value(card.substr(10));
    double v = 0;
    if (value >> v) h_[name] = v;
  }
  for (const char* k : {"CRVAL1", "CRVAL2", "CRPIX1", "CRPIX2", "CD1_1", "CD1_2", "CD2_1", "CD2_2"})
    if (!h_.count(k)) throw std::runtime_error(path + ": no " + k);
}

double WcsReference::key(const std::string& k, double fallback) const {
  const auto it = h_.find(k);
  return it == h_.end() ? fallback : it->second;
}

double WcsReference::sip(const std::string& prefix, double u, double v) const {
  const int order = static_cast<int>(key(prefix + "_ORDER"));
  double s = 0;
  for (int p = 0; p <= order; ++p)
    for (int q = 0; p + q <= order; ++q)
      s += key(prefix + "_" + std::to_string(p) + "_" + std::to_string(q)) * std::pow(u, p) *
           std::pow(v, q);
  return s;
}

void WcsReference::pixelToSky(double x, double y, double& ra, double& dec) const {
  if (rows_doubled_) y = 2 * (y + 0.5) - 0.5;
  const double u = x + 1 - key("CRPIX1"), v = y + 1 - key("CRPIX2");
  const double U = u + sip("A", u, v), V = v + sip("B", u, v);
  const double xi = (key("CD1_1") * U + key("CD1_2") * V) * kDeg;
  const double eta = (key("CD2_1") * U + key("CD2_2") * V) * kDeg;
  const double ra0 = key("CRVAL1") * kDeg, de0 = key("CRVAL2") * kDeg;
  const double d = std::cos(de0) - eta * std::sin(de0);
  ra = ra0 + std::atan2(xi, d);
  dec = std::atan2(std::sin(de0) + eta * std::cos(de0), std::hypot(xi, d));
}

bool WcsReference::skyToPixel(double ra, double dec, double& x, double& y) const {
  const double ra0 = key("CRVAL1") * kDeg, de0 = key("CRVAL2") * kDeg;
  const double c = std::sin(dec) * std::sin(de0) + std::cos(dec) * std::cos(de0) * std::cos(ra - ra0);
  if (c <= 0) return false;
  const double xi = std::cos(dec) * std::sin(ra - ra0) / c / kDeg;
  const double eta =
      (std::sin(dec) * std::cos(de0) - std::cos(dec) * std::sin(de0) * std::cos(ra - ra0)) / c / kDeg;
  const double det = key("CD1_1") * key("CD2_2") - key("CD1_2") * key("CD2_1");
  const double U = (key("CD2_2") * xi - key("CD1_2") * eta) / det;
  const double V = (-key("CD2_1") * xi + key("CD1_1") * eta) / det;
  const double u = U + sip("AP", U, V), v = V + sip("BP", U, V);
  x = u + key("CRPIX1") - 1;
  y = v + key("CRPIX2") - 1;
  if (rows_doubled_) y = (y + 0.5) / 2 - 0.5;
  return true;
}

double separationArcsec(double ra1, double dec1, double ra2, double dec2) {
  const double h = std::pow(std::sin((dec2 - dec1) / 2), 2) +
                   std::cos(dec1) * std::cos(dec2) * std::pow(std::sin((ra2 - ra1) / 2), 2);
  return 2 * std::asin(std::sqrt(std::min(1.0, std::max(0.0, h)))) / kDeg * 3600;
}

}  // namespace st::test

#include "common/output_file.hpp"
#include "app/testbed/star_list.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "common/attitude.hpp"
#include "common/conventions.hpp"
#include "common/errors.hpp"

namespace st::app {

namespace {
constexpr const char* kHeader = "id,screen_x_px,screen_y_px,mag,ra_deg,dec_deg";
constexpr const char* kTag = "# startracker testbed star list; attitude_ypr_deg =";
}  // namespace

void writeStarList(const std::string& path, const DisplayStarList& list) {
  std::ostringstream f;
  char buf[256];
  std::snprintf(buf, sizeof buf, "%s %.12g %.12g %.12g\n%s\n", kTag, list.attitude_ypr_deg.x(),
                list.attitude_ypr_deg.y(), list.attitude_ypr_deg.z(), kHeader);
  f << buf;
  for (const auto& s : list.stars) {
    double ra = 0, dec = 0;
    raDecFromVector(s.u_sky, ra, dec);
    std::snprintf(buf, sizeof buf, "%u,%.6f,%.6f,%.3f,%.9f,%.9f\n", s.id, s.screen_px.x(),
                  s.screen_px.y(), s.mag, rad2deg(ra), rad2deg(dec));
    f << buf;
  }
  writeFileAtomically(path, f.str());
}

DisplayStarList readStarList(const std::string& path) {
  std::ifstream f(path);
  if (!f) throw InputError(path + ": cannot open the star list");
  DisplayStarList list;
  std::string line;
  int n = 0;
  bool header = false;
  while (std::getline(f, line)) {
    ++n;
    const std::string where = path + ":" + std::to_string(n) + ": ";
    if (line.empty()) continue;
    if (line.rfind(kTag, 0) == 0) {
      std::istringstream is(line.substr(std::string(kTag).size()));
      double y, p, r;
      if (!(is >> y >> p >> r) || !std::isfinite(y + p + r))
        throw InputError(where + "attitude_ypr_deg needs three numbers");
      list.attitude_ypr_deg = Vec3(y, p, r);
      continue;
    }
    if (line[0] == '#') continue;
    if (!header) {
      if (line != kHeader) throw InputError(where + "expected the header '" + std::string(kHeader) + "'");
      header = true;
      continue;
    }
    std::istringstream is(line);
    std::string cell;
    std::vector<double> v;
    while (std::getline(is, cell, ',')) {
      char* end = nullptr;
      const double x = std::strtod(cell.c_str(), &end);
      if (cell.empty() || *end != '\0' || !std::isfinite(x))
        throw InputError(where + "'" + cell + "' is not a number");
      v.push_back(x);
    }
    if (v.size() != 6) throw InputError(where + "expected 6 columns, got " + std::to_string(v.size()));
    testbed::DisplayStar s;
    s.id = static_cast<uint32_t>(v[0]);
    s.screen_px = Vec2(v[1], v[2]);
    s.mag = v[3];
    s.u_sky = unitVectorFromRaDec(deg2rad(v[4]), deg2rad(v[5]));
    list.stars.push_back(s);
  }
  if (!header) throw InputError(path + ": not a testbed star list (no header line)");
  if (list.stars.size() < 3)
    throw InputError(path + ": " + std::to_string(list.stars.size()) +
                     " stars; the near-field solver needs at least 3");
  return list;
}

}  // namespace st::app

#include "app/montecarlo/mc_options.hpp"

#include <cmath>
#include <cstdio>
#include <sstream>

#include "common/errors.hpp"
#include "common/shard.hpp"

namespace st::app::mc {

std::string fmt(double v, int digits) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char b[48];
  std::snprintf(b, sizeof b, "%.*g", digits, v);
  return b;
}

std::string joinList(const std::vector<double>& v) {
  std::string s;
  for (std::size_t i = 0; i < v.size(); ++i) s += (i ? "," : "") + fmt(v[i], 17);
  return s;
}

std::string joinList(const std::vector<std::string>& v) {
  std::string s;
  for (std::size_t i = 0; i < v.size(); ++i) s += (i ? "," : "") + v[i];
  return s;
}

void parseShard(const std::string& text, int& index, int& count) {
  const Shard s = Shard::parse(text);
  index = s.index;
  count = s.count;
}

std::map<std::string, std::string> McOptions::toKeyValues() const {
  return {{"experiment", experiment},
          {"runs", std::to_string(runs)},
          {"seed", std::to_string(seed)},
          {"fov_deg", fmt(fov_deg, 17)},
          {"width", std::to_string(width)},
          {"height", std::to_string(height)},
          {"mag_limit", fmt(mag_limit, 17)},
          {"mags", joinList(mags)},
          {"fovs_deg", joinList(fovs_deg)},
          {"algorithms", joinList(algorithms)},
          {"solvers", joinList(solvers)},
          {"noise_px", fmt(noise_px, 17)},
          {"merge_arcsec", fmt(merge_arcsec, 17)},
          {"catalog", catalog},
          {"field_stop_deg", fmt(field_stop_deg, 17)},
          {"heads", std::to_string(heads)}};
}

namespace {

struct KvReader {
  const std::map<std::string, std::string>& kv;
  const std::string& source;
  const std::string& get(const std::string& key) const {
    auto it = kv.find(key);
    if (it == kv.end()) throw InputError(source + ": missing key '" + key + "'");
    return it->second;
  }
  [[noreturn]] void bad(const std::string& key) const {
    throw InputError(source + ": bad value for '" + key + "': '" + get(key) + "'");
  }
  double num(const std::string& key) const {
    try {
      std::size_t used = 0;
      const double v = std::stod(get(key), &used);
      if (used == get(key).size()) return v;
    } catch (const std::exception&) {
    }
    bad(key);
  }
  uint64_t uint(const std::string& key) const {
    try {
      std::size_t used = 0;
      const uint64_t v = std::stoull(get(key), &used);
      if (used == get(key).size()) return v;
    } catch (const std::exception&) {
    }
    bad(key);
  }
  std::vector<std::string> strings(const std::string& key) const {
    std::vector<std::string> out;
    std::stringstream ss(get(key));
    std::string item;
    while (std::getline(ss, item, ','))
      if (!item.empty()) out.push_back(item);
    return out;
  }
  std::vector<double> nums(const std::string& key) const {
    std::vector<double> out;
    for (const std::string& s : strings(key)) {
      try {
        out.push_back(std::stod(s));
      } catch (const std::exception&) {
        bad(key);
      }
    }
    return out;
  }
};

}  // namespace

McOptions McOptions::fromKeyValues(const std::map<std::string, std::string>& kv,
                                   const std::string& source) {
  const KvReader r{kv, source};
  McOptions o;
  o.experiment = r.get("experiment");
  o.runs = r.uint("runs");
  o.seed = r.uint("seed");
  o.fov_deg = r.num("fov_deg");
  o.width = static_cast<int>(r.uint("width"));
  o.height = static_cast<int>(r.uint("height"));
  o.mag_limit = r.num("mag_limit");
  o.mags = r.nums("mags");
  o.fovs_deg = r.nums("fovs_deg");
  o.algorithms = r.strings("algorithms");
  o.solvers = r.strings("solvers");
  o.noise_px = r.num("noise_px");
  o.merge_arcsec = r.num("merge_arcsec");
  o.catalog = r.get("catalog");
  o.field_stop_deg = r.num("field_stop_deg");
  o.heads = static_cast<int>(r.uint("heads"));
  return o;
}

std::string McOptions::commandLine() const {
  std::string s = "startracker montecarlo " + experiment + " --runs " + std::to_string(runs) +
                  " --seed " + std::to_string(seed) + " --fov-deg " + fmt(fov_deg) + " --size " +
                  std::to_string(width) + " " + std::to_string(height) + " --mag-limit " +
                  fmt(mag_limit) + " --noise-px " + fmt(noise_px);
  if (!mags.empty()) s += " --mags " + joinList(mags);
  if (!fovs_deg.empty()) s += " --fovs " + joinList(fovs_deg);
  if (!algorithms.empty()) s += " --algorithms " + joinList(algorithms);
  if (!solvers.empty()) s += " --solvers " + joinList(solvers);
  if (merge_arcsec != 60.0) s += " --merge-arcsec " + fmt(merge_arcsec);
  if (!catalog.empty()) s += " --catalog " + catalog;
  if (field_stop_deg > 0) s += " --field-stop-deg " + fmt(field_stop_deg);
  if (heads != 1) s += " --heads " + std::to_string(heads);
  return s;
}

}  // namespace st::app::mc

#include "sensors/mrpt/ini_reader.hpp"

#include <mrpt/config/CConfigFileBase.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "common/errors.hpp"

namespace st {

std::string IniReader::where(const std::string& sec, const std::string& key) const {
  const std::string prefix = source.empty() ? "" : source + ": ";
  if (mrpt_safe) return prefix + "section '" + sec + "' key '" + key + "'";
  return prefix + "[" + sec + "] " + key;
}

std::string IniReader::where(const std::string& sec) const {
  const std::string prefix = source.empty() ? "" : source + ": ";
  return prefix + (mrpt_safe ? "section '" + sec + "'" : "[" + sec + "]");
}

bool IniReader::has(const std::string& sec, const std::string& key) const {
  return !cfg.read_string(sec, key, "", false).empty();
}

std::string IniReader::str(const std::string& sec, const std::string& key,
                           const std::string& def) const {
  const std::string v = cfg.read_string(sec, key, "", false);
  return v.empty() ? def : v;
}

double IniReader::num(const std::string& sec, const std::string& key, double def) const {
  const std::string v = cfg.read_string(sec, key, "", false);
  if (v.empty()) return def;
  try {
    std::size_t pos = 0;
    const double d = std::stod(v, &pos);
    if (v.find_first_not_of(" \t\r", pos) == std::string::npos && std::isfinite(d)) return d;
  } catch (const std::exception&) {
  }
  throw InputError(where(sec, key) + " = '" + v + "': not a number");
}

int IniReader::integer(const std::string& sec, const std::string& key, int def) const {
  const double d = num(sec, key, def);
  if (d != std::floor(d) || std::abs(d) > 1e9)
    throw InputError(where(sec, key) + ": not an integer");
  return static_cast<int>(d);
}

bool IniReader::boolean(const std::string& sec, const std::string& key, bool def) const {
  std::string v = cfg.read_string(sec, key, "", false);
  if (v.empty()) return def;
  std::transform(v.begin(), v.end(), v.begin(), ::tolower);
  if (v == "true" || v == "1" || v == "yes" || v == "on") return true;
  if (v == "false" || v == "0" || v == "no" || v == "off") return false;
  throw InputError(where(sec, key) + " = '" + v + "': not a boolean (true/false)");
}

void IniReader::onlyKeys(const std::string& sec, const std::set<std::string>& allowed) const {
  if (!cfg.sectionExists(sec)) return;
  std::vector<std::string> keys;
  cfg.getAllKeys(sec, keys);
  for (const auto& k : keys) {
    if (allowed.count(k)) continue;
    std::string list;
    for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
    throw InputError(where(sec, k) + ": unknown key (known: " + list + ")");
  }
}

}  // namespace st

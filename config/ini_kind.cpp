#include "config/ini_kind.hpp"

#include <mrpt/config/CConfigFileBase.h>

#include <vector>

#include "common/errors.hpp"

namespace st {

namespace {

bool endsWith(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

/// "a, b , c" -> {"a", "b", "c"}
std::vector<std::string> commaList(const std::string& v) {
  std::vector<std::string> out;
  std::size_t pos = 0;
  while (pos <= v.size()) {
    const std::size_t end = std::min(v.find(',', pos), v.size());
    const std::string item = v.substr(pos, end - pos);
    const auto a = item.find_first_not_of(" \t");
    if (a != std::string::npos) out.push_back(item.substr(a, item.find_last_not_of(" \t") + 1 - a));
    pos = end + 1;
  }
  return out;
}

}  // namespace

const std::set<std::string>& trackerIniSections() {
  static const std::set<std::string> s = {"filter", "navigator", "pipeline", "database", "camera"};
  return s;
}

bool isLiveIni(const IniReader& r) {
  if (r.cfg.sectionExists("global")) return true;
  std::vector<std::string> all;
  r.cfg.getAllSections(all);
  for (const auto& s : all)
    if (r.exists(s, "driver")) return true;
  return false;
}

std::set<std::string> liveIniSections(const IniReader& r) {
  std::set<std::string> out = {"global", "filter", "navigator"};
  std::vector<std::string> all;
  r.cfg.getAllSections(all);
  for (const auto& s : all) {
    if (!r.exists(s, "driver")) continue;
    out.insert(s);
    std::vector<std::string> keys;
    r.cfg.getAllKeys(s, keys);
    for (const auto& k : keys)
      if (endsWith(k, "_section") || endsWith(k, "_sections"))
        for (const auto& named : commaList(r.cfg.read_string(s, k, "", false))) out.insert(named);
  }
  return out;
}

std::string iniKind(const IniReader& r) {
  if (isLiveIni(r)) return "a live .ini";
  if (r.cfg.sectionExists("scenario")) return "a scenario file";
  if (r.cfg.sectionExists(kMontecarloRunSection)) return "a montecarlo run file";
  for (const char* sec : {"filter", "navigator", "pipeline", "database"})
    if (r.cfg.sectionExists(sec)) return "a tracker file";
  return "";
}

void requireIniKind(const IniReader& r, const std::string& expected, const std::string& who) {
  const std::string kind = iniKind(r);
  if (kind == expected) return;
  throw InputError(r.source + ": " + (kind.empty() ? "not " + expected : "this is " + kind) +
                   "; " + who + " takes " + expected);
}

}  // namespace st

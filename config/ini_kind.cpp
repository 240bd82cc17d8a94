#include "config/ini_kind.hpp"

#include <mrpt/config/CConfigFileBase.h>

#include <vector>

#include "common/errors.hpp"
#include "config/ini_value.hpp"

namespace st {

namespace {

bool endsWith(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
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
        for (const auto& named : splitIniList(r.cfg.read_string(s, k, "", false))) out.insert(named);
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

#include "config/ini_reader.hpp"

#include <mrpt/config/CConfigFile.h>
#include <mrpt/config/CConfigFileBase.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <vector>

#include "common/errors.hpp"
#include "common/number_list.hpp"

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

std::string IniReader::whereKey(const std::string& sec, const std::string& key) const {
  return where(sec) + " key '" + key + "'";
}

bool IniReader::has(const std::string& sec, const std::string& key) const {
  return !cfg.read_string(sec, key, "", false).empty();
}

bool IniReader::exists(const std::string& sec, const std::string& key) const {
  return cfg.keyExists(sec, key);
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

uint64_t IniReader::uint64(const std::string& sec, const std::string& key, uint64_t def) const {
  const std::string v = cfg.read_string(sec, key, "", false);
  if (v.empty()) return def;
  // Parsed as an integer, not through double: seeds use all 64 bits.
  const auto first = v.find_first_not_of(" \t");
  if (first != std::string::npos && std::isdigit(static_cast<unsigned char>(v[first]))) {
    try {
      std::size_t pos = 0;
      const unsigned long long u = std::stoull(v, &pos);
      if (v.find_first_not_of(" \t\r", pos) == std::string::npos) return u;
    } catch (const std::exception&) {
    }
  }
  throw InputError(where(sec, key) + " = '" + v + "': not a non-negative integer");
}

bool IniReader::boolean(const std::string& sec, const std::string& key, bool def) const {
  std::string v = cfg.read_string(sec, key, "", false);
  if (v.empty()) return def;
  std::transform(v.begin(), v.end(), v.begin(), ::tolower);
  if (v == "true" || v == "1" || v == "yes" || v == "on") return true;
  if (v == "false" || v == "0" || v == "no" || v == "off") return false;
  throw InputError(where(sec, key) + " = '" + v + "': not a boolean (true/false)");
}

std::vector<double> IniReader::numbers(const std::string& sec, const std::string& key,
                                       const std::vector<double>& def) const {
  if (!exists(sec, key)) return def;
  return parseNumberList(cfg.read_string(sec, key, "", false), where(sec, key));
}

void IniReader::onlyKeys(const std::string& sec, const std::set<std::string>& allowed) const {
  if (!cfg.sectionExists(sec)) return;
  std::vector<std::string> keys;
  cfg.getAllKeys(sec, keys);
  const std::vector<std::string> known(allowed.begin(), allowed.end());
  for (const auto& k : keys) {
    if (allowed.count(k)) continue;
    const std::string near = closestKey(k, known);
    if (!near.empty())
      throw InputError(whereKey(sec, k) + ": unknown key; did you mean '" + near + "'?");
    std::string list;
    for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
    throw InputError(whereKey(sec, k) + ": unknown key (known: " + list + ")");
  }
}

void IniReader::onlySections(const std::set<std::string>& allowed, const std::string& kind) const {
  std::vector<std::string> sections;
  cfg.getAllSections(sections);
  const std::vector<std::string> known(allowed.begin(), allowed.end());
  for (const auto& s : sections) {
    if (s.empty() || allowed.count(s)) continue;  // "": keys before any section header
    const std::string near = closestKey(s, known);
    std::string list;
    for (const auto& a : allowed) list += (list.empty() ? "[" : ", [") + a + "]";
    throw InputError(where(s) + ": unknown section" +
                     (near.empty() ? "" : "; did you mean [" + near + "]?") + " (" + kind +
                     " has " + list + ")");
  }
}

void refuseDuplicateKeys(const std::string& text, const std::string& source) {
  std::set<std::pair<std::string, std::string>> seen;
  std::string section;
  std::size_t line_no = 0, pos = 0;
  while (pos <= text.size()) {
    const std::size_t end = std::min(text.find('\n', pos), text.size());
    std::string line = text.substr(pos, end - pos);
    pos = end + 1;
    ++line_no;
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos) continue;
    line = line.substr(first, line.find_last_not_of(" \t\r") + 1 - first);
    // Comments and MRPT's preprocessor lines (@define, @include) are not keys.
    if (line[0] == ';' || line[0] == '#' || line[0] == '@' || line.rfind("//", 0) == 0) continue;
    if (line[0] == '[') {
      section = line.substr(1, line.find(']') - 1);
      continue;
    }
    const auto eq = line.find('=');
    if (eq == std::string::npos) continue;
    std::string key = line.substr(0, eq);
    key.erase(key.find_last_not_of(" \t") + 1);
    if (!seen.insert({section, key}).second)
      throw InputError(source + ":" + std::to_string(line_no) + ": [" + section + "] key '" +
                       key + "' is written twice (which one was meant? MRPT would keep the last)");
  }
}

int editDistance(const std::string& a, const std::string& b) {
  // One row of the Wagner-Fischer table: keys are short, and this runs only on an error.
  std::vector<int> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = static_cast<int>(j);
  for (std::size_t i = 1; i <= a.size(); ++i) {
    int diag = row[0];
    row[0] = static_cast<int>(i);
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const int up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diag = up;
    }
  }
  return row[b.size()];
}

std::string closestKey(const std::string& key, const std::vector<std::string>& candidates) {
  std::string best;
  int best_d = 0;
  for (const auto& c : candidates) {
    const int d = editDistance(key, c);
    if (best.empty() || d < best_d) {
      best = c;
      best_d = d;
    }
  }
  // Farther than this is not a typo but a different word: listing the keys helps more.
  const int limit = std::max(2, static_cast<int>(key.size()) / 3);
  return best_d <= limit ? best : "";
}

std::unique_ptr<mrpt::config::CConfigFile> openIniFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot be read");
  std::stringstream text;
  text << in.rdbuf();
  refuseDuplicateKeys(text.str(), path);
  try {
    return std::make_unique<mrpt::config::CConfigFile>(path);
  } catch (const std::exception& e) {
    std::string why = e.what();
    // MRPT's message: a banner line, the error line, then a call stack.
    const auto banner = why.find("====\n");
    if (banner != std::string::npos) why = why.substr(banner + 5);
    why = why.substr(0, why.find('\n'));
    throw InputError(path + ": not a readable .ini file (" + why + ")");
  }
}

}  // namespace st

#include "config/printer_registry.hpp"

#include <mrpt/config/CConfigFileBase.h>

#include <algorithm>
#include <set>

#include "common/errors.hpp"

namespace st {

namespace {
bool isHeader(const std::string& line) { return !line.empty() && line[0] == '['; }

/// Only the block of section `sec` from a printed configuration (a schema may print several).
std::string onlySection(const std::string& text, const std::string& sec) {
  std::string out, line;
  bool keep = false;
  std::size_t pos = 0;
  while (pos < text.size()) {
    const std::size_t nl = std::min(text.find('\n', pos), text.size());
    line = text.substr(pos, nl - pos);
    if (isHeader(line)) keep = line == "[" + sec + "]";
    if (keep) out += line + "\n";
    pos = nl + 1;
  }
  return out;
}
}  // namespace

std::function<std::vector<std::string>(const IniReader&, const std::string&)> sectionNamed(
    const std::string& sec) {
  return [sec](const IniReader& r, const std::string&) {
    return r.cfg.sectionExists(sec) ? std::vector<std::string>{sec} : std::vector<std::string>{};
  };
}

decltype(SchemaPrinter::print) perSection(
    std::function<std::string(const IniReader& r, const std::string& section)> print_one) {
  return [print_one](const IniReader& r, const std::vector<std::string>& sections) {
    std::string out;
    for (const auto& s : sections) out += (out.empty() ? "" : "\n") + print_one(r, s);
    return out;
  };
}

std::string SchemaPrinters::print(const IniReader& r, const std::string& wanted) const {
  std::vector<std::string> all_sections;
  r.cfg.getAllSections(all_sections);
  if (!wanted.empty() && !r.cfg.sectionExists(wanted))
    throw InputError(r.where(wanted) + ": no such section");
  std::set<std::string> claimed;
  std::string out;
  for (const SchemaPrinter& p : printers_) {
    std::vector<std::string> secs = p.find(r, wanted);
    secs.erase(std::remove_if(secs.begin(), secs.end(),
                              [&](const std::string& s) { return claimed.count(s) > 0; }),
               secs.end());
    if (secs.empty()) continue;
    if (!wanted.empty() && std::find(secs.begin(), secs.end(), wanted) == secs.end()) continue;
    claimed.insert(secs.begin(), secs.end());
    std::string text = p.print(r, secs);
    if (!wanted.empty()) text = onlySection(text, wanted);
    out += "# ---- " + p.name + " ----\n" + text + "\n";
  }
  if (out.empty())
    throw InputError(r.source + ": no known schema in " +
                     (wanted.empty() ? "the file" : "section [" + wanted + "]") + " (known: " +
                     [&] {
                       std::string names;
                       for (const auto& p : printers_) names += (names.empty() ? "" : ", ") + p.name;
                       return names;
                     }() + ")");
  if (wanted.empty())
    for (const auto& s : all_sections)
      if (!claimed.count(s) && !s.empty())
        out += "# [" + s + "]: no schema registered for this section; not printed\n";
  return out;
}

}  // namespace st

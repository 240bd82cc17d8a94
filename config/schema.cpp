#include "config/schema.hpp"

#include <cstdio>
#include <cstdlib>

#include <sstream>

namespace st {

std::string formatIniKey(const std::string& key, const std::string& value, const std::string& help) {
  return "# " + help + "\n" + key + " = " + value + "\n";
}

std::string formatIniNumberThrough(double shown, double stored,
                                   const std::function<double(const double&)>& to) {
  char buf[40];
  for (int digits = 6; digits <= 17; ++digits) {
    std::snprintf(buf, sizeof buf, "%.*g", digits, shown);
    if (to(std::strtod(buf, nullptr)) == stored) return buf;
  }
  return formatIniNumber(shown);
}

void throwBadChoice(const IniReader& r, const std::string& sec, const std::string& key,
                    const std::string& value, const std::vector<std::string>& names) {
  std::string list;
  for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
  const std::string near = closestKey(value, names);
  throw InputError(r.whereKey(sec, key) + " = '" + value + "': expected one of " + list +
                   (near.empty() ? "" : "; did you mean '" + near + "'?"));
}

void refuseRenamedKeys(const IniReader& r, const std::string& sec,
                       const std::vector<std::pair<std::string, std::string>>& renamed) {
  for (const auto& [old_key, new_keys] : renamed) {
    if (!r.exists(sec, old_key)) continue;
    std::string names;  // "'a'" or "'a' and 'b'" (a key split in two)
    std::istringstream in(new_keys);
    for (std::string k; in >> k;) names += (names.empty() ? "'" : " and '") + k + "'";
    throw InputError(r.whereKey(sec, old_key) + ": renamed to " + names);
  }
}

}  // namespace st

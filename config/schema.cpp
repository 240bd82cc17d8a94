#include "config/schema.hpp"

namespace st {

std::string formatIniKey(const std::string& key, const std::string& value, const std::string& help) {
  return "# " + help + "\n" + key + " = " + value + "\n";
}

void throwBadChoice(const IniReader& r, const std::string& sec, const std::string& key,
                    const std::string& value, const std::vector<std::string>& names) {
  std::string list;
  for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
  const std::string near = closestKey(value, names);
  throw InputError(r.whereKey(sec, key) + " = '" + value + "': expected one of " + list +
                   (near.empty() ? "" : "; did you mean '" + near + "'?"));
}

}  // namespace st

#include "common/number_list.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "common/errors.hpp"

namespace st {

std::vector<double> parseNumberList(const std::string& text, const std::string& where) {
  std::string s = text;
  for (char& c : s)
    if (c == '[' || c == ']' || c == ',' || c == ';') c = ' ';
  std::istringstream is(s);
  std::vector<double> out;
  std::string tok;
  while (is >> tok) {
    try {
      std::size_t used = 0;
      out.push_back(std::stod(tok, &used));
      // inf and nan are no setting (a scalar key refuses them too).
      if (used != tok.size() || !std::isfinite(out.back())) throw std::invalid_argument(tok);
    } catch (const std::exception&) {
      throw InputError(where + ": '" + tok + "' is not a number");
    }
  }
  return out;
}

}  // namespace st

#include "common/shard.hpp"

#include <stdexcept>

#include "common/errors.hpp"

namespace st {

Shard Shard::parse(const std::string& text, const std::string& flag) {
  const auto slash = text.find('/');
  long i = -1, n = -1;
  if (slash != std::string::npos) {
    const std::string a = text.substr(0, slash), b = text.substr(slash + 1);
    std::size_t used_i = 0, used_n = 0;
    try {
      i = std::stol(a, &used_i);
      n = std::stol(b, &used_n);
    } catch (const std::exception&) {
      i = -1;
    }
    if (used_i != a.size() || used_n != b.size()) i = -1;
  }
  if (i < 0 || n < 1 || i >= n || n > 1000000)
    throw InputError(flag + " '" + text + "': expected i/N with 0 <= i < N (e.g. 0/4)");
  return Shard{static_cast<int>(i), static_cast<int>(n)};
}

}  // namespace st

#include "common/utc_time.hpp"

#include <cstdio>
#include <ctime>

#include "common/errors.hpp"

namespace st {

double parseUtc(const std::string& text, const std::string& where) {
  int Y = 0, M = 0, D = 0, h = 0, m = 0;
  double s = 0;
  char sep = 0;
  if (std::sscanf(text.c_str(), "%d-%d-%d%c%d:%d:%lf", &Y, &M, &D, &sep, &h, &m, &s) != 7 ||
      (sep != 'T' && sep != ' ') || M < 1 || M > 12 || D < 1 || D > 31 || h < 0 || h > 23 ||
      m < 0 || m > 59 || s < 0 || s >= 61)
    throw InputError(where + ": '" + text + "' is not a UTC time YYYY-MM-DDTHH:MM:SS");
  std::tm tm{};
  tm.tm_year = Y - 1900;
  tm.tm_mon = M - 1;
  tm.tm_mday = D;
  tm.tm_hour = h;
  tm.tm_min = m;
  const double whole = static_cast<double>(timegm(&tm));
  return whole + s;
}

}  // namespace st

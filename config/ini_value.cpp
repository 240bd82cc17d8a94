#include "config/ini_value.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "common/errors.hpp"

namespace st {

std::string formatIniNumber(double v) {
  // %.17g always reads back exactly but prints 0.1 as 0.10000000000000001: take the first
  // precision that reads back, so printed configurations stay readable.
  char buf[40];
  for (int digits = 6; digits <= 17; ++digits) {
    std::snprintf(buf, sizeof buf, "%.*g", digits, v);
    if (std::strtod(buf, nullptr) == v) break;
  }
  return buf;
}

std::string formatIniNumbers(const std::vector<double>& v, bool brackets) {
  std::string s;
  for (double x : v) s += (s.empty() ? "" : " ") + formatIniNumber(x);
  return brackets ? "[" + s + "]" : s;
}

std::vector<std::string> splitIniList(const std::string& text) {
  std::vector<std::string> out;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t comma = std::min(text.find(',', start), text.size());
    const std::string item = text.substr(start, comma - start);
    const auto a = item.find_first_not_of(" \t"), b = item.find_last_not_of(" \t\r");
    if (a != std::string::npos) out.push_back(item.substr(a, b - a + 1));
    start = comma + 1;
  }
  return out;
}

std::string IniCodec<std::vector<std::string>>::write(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += (s.empty() ? "" : ",") + x;
  return s;
}

void readIniVector(const IniReader& r, const std::string& s, const std::string& k, double* out,
                   int n) {
  const std::vector<double> v = r.numbers(s, k, {});
  if (static_cast<int>(v.size()) != n)
    throw InputError(r.whereKey(s, k) + ": expected " + (n == 2 ? std::string("two") : "three") + " numbers, got " +
                     std::to_string(v.size()));
  for (int i = 0; i < n; ++i) out[i] = v[static_cast<std::size_t>(i)];
}

void IniCodec<std::vector<std::pair<double, double>>>::read(const IniReader& r,
                                                             const std::string& s,
                                                             const std::string& k, Pairs& v) {
  const std::vector<double> x = r.numbers(s, k, {});
  if (x.size() % 2 != 0)
    throw InputError(r.whereKey(s, k) + ": must hold pairs: t0 t1 [t0 t1 ...]");
  v.clear();
  for (std::size_t i = 0; i < x.size(); i += 2) v.emplace_back(x[i], x[i + 1]);
}

std::string IniCodec<std::vector<std::pair<double, double>>>::write(const Pairs& v) {
  std::vector<double> x;
  for (const auto& p : v) {
    x.push_back(p.first);
    x.push_back(p.second);
  }
  return formatIniNumbers(x);
}

void IniCodec<uint32_t>::read(const IniReader& r, const std::string& s, const std::string& k,
                             uint32_t& v) {
  const uint64_t u = r.uint64(s, k, v);
  if (u > 0xFFFFFFFFull) throw InputError(r.where(s, k) + ": more than 32 bits");
  v = static_cast<uint32_t>(u);
}

void IniCodec<long>::read(const IniReader& r, const std::string& s, const std::string& k, long& v) {
  const double d = r.num(s, k, static_cast<double>(v));
  if (d != std::floor(d) || std::abs(d) > 9007199254740992.0)
    throw InputError(r.where(s, k) + ": not an integer");
  v = static_cast<long>(d);
}

}  // namespace st

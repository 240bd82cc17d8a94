#include "app/cli/validators.hpp"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>

namespace st::app::cli {
namespace {

bool isBound(long double v) { return std::isfinite(v) && std::fabs(v) < 1e300L; }

/// A type's own limit (2^64 - 1 for a seed) is checked but not worth stating in the rule.
bool isStated(long double v) { return isBound(v) && std::fabs(v) < 1e18L; }

/// Decimal digits with an optional sign, nothing else.
bool parseWhole(const std::string& text, long double* out) {
  std::size_t i = 0;
  const bool negative = !text.empty() && text[0] == '-';
  if (!text.empty() && (text[0] == '-' || text[0] == '+')) i = 1;
  if (i == text.size()) return false;
  long double v = 0;
  for (; i < text.size(); ++i) {
    if (text[i] < '0' || text[i] > '9') return false;
    v = v * 10 + (text[i] - '0');
  }
  *out = negative ? -v : v;
  return true;
}

bool parseReal(const std::string& text, double* out) {
  if (text.empty() || std::isspace(static_cast<unsigned char>(text[0]))) return false;
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(text.c_str(), &end);
  if (end != text.c_str() + text.size()) return false;
  *out = v;  // +-inf on overflow (ERANGE): refused as not finite
  return true;
}

/// "from 1 to 10", ">= 1", "<= 10" or "" (no bound).
std::string rangeWords(long double min, long double max, Bound lo, Bound hi) {
  const std::string ge = lo == Bound::kClosed ? ">= " : "> ";
  const std::string le = hi == Bound::kClosed ? "<= " : "< ";
  if (isStated(min) && isStated(max)) {
    if (lo == Bound::kClosed && hi == Bound::kClosed)
      return "from " + formatNumber(min) + " to " + formatNumber(max);
    return ge + formatNumber(min) + " and " + le + formatNumber(max);
  }
  if (isStated(min)) return ge + formatNumber(min);
  if (isStated(max)) return le + formatNumber(max);
  return "";
}

/// The help text's short form: "in [1, 10]", ">= 1", "in (0, 180)".
std::string rangeHelp(long double min, long double max, Bound lo, Bound hi) {
  if (isStated(min) && isStated(max))
    return std::string("in ") + (lo == Bound::kClosed ? "[" : "(") + formatNumber(min) + ", " +
           formatNumber(max) + (hi == Bound::kClosed ? "]" : ")");
  return rangeWords(min, max, lo, hi);
}

std::string withRange(const std::string& kind, const std::string& range) {
  return range.empty() ? kind : kind + " " + range;
}

}  // namespace

std::string formatNumber(long double v) {
  char b[64];
  if (std::isfinite(v) && v == std::floor(v) && std::fabs(v) < 1e20L)
    std::snprintf(b, sizeof b, "%.0Lf", v);
  else
    std::snprintf(b, sizeof b, "%.15Lg", v);
  return b;
}

CLI::Validator WholeNumber(long double min, long double max) {
  const std::string rule = withRange("a whole number", rangeWords(min, max, Bound::kClosed,
                                                                   Bound::kClosed));
  auto check = [=](std::string& text) -> std::string {
    long double v = 0;
    if (!parseWhole(text, &v)) return "must be " + rule + ", got '" + text + "'";
    if (isBound(min) && v < min) return "must be a whole number >= " + formatNumber(min) + ", got " + text;
    if (isBound(max) && v > max) return "must be a whole number <= " + formatNumber(max) + ", got " + text;
    return {};
  };
  return CLI::Validator(check, rangeHelp(min, max, Bound::kClosed, Bound::kClosed));
}

CLI::Validator Number(double min, double max, Bound min_bound, Bound max_bound) {
  const std::string range = rangeWords(min, max, min_bound, max_bound);
  const std::string rule = withRange("a number", range);
  auto check = [=](std::string& text) -> std::string {
    double v = 0;
    if (!parseReal(text, &v)) return "must be " + rule + ", got '" + text + "'";
    if (!std::isfinite(v)) return "must be a finite number" + (range.empty() ? "" : " " + range) +
                                  ", got " + text;
    const bool below = isBound(min) && (min_bound == Bound::kClosed ? v < min : v <= min);
    const bool above = isBound(max) && (max_bound == Bound::kClosed ? v > max : v >= max);
    if (below)
      return "must be a number " + rangeWords(min, kNoBound, min_bound, max_bound) + ", got " + text;
    if (above)
      return "must be a number " + rangeWords(-kNoBound, max, min_bound, max_bound) + ", got " + text;
    return {};
  };
  return CLI::Validator(check, rangeHelp(min, max, min_bound, max_bound));
}

CLI::Validator FiniteNumber() { return Number(-kNoBound, kNoBound); }

void applyTypeChecks(CLI::App& app) {
  for (CLI::Option* opt : app.get_options()) {
    if (opt->get_type_size_max() == 0) continue;  // a flag
    // `--size W H IMAGE`: an option of a fixed count takes that many values and no more.
    // CLI11 leaves a vector option greedy after expected(N) and only spares the arguments a
    // *required* positional still needs, so an optional IMAGE (solve's, with --files-from)
    // would be eaten as a third value.
    if (!opt->get_positional() && opt->get_expected_min() == opt->get_expected_max() &&
        opt->get_expected_max() > 1)
      opt->allow_extra_args(false);
    const std::string full = opt->get_type_name();
    const std::string type = full.substr(0, full.find(':'));
    // An empty description keeps the help text as the command wrote it.
    // CLI11 2.1 saturates a uint64 past its range without a word; narrower types get its
    // conversion error, worded by parse_errors.cpp.
    if (type == "UINT")
      opt->check(WholeNumber(0, kMaxU64).description(""));
    else if (type == "INT")
      opt->check(WholeNumber(kMinI64, kMaxI64).description(""));
    else if (type == "FLOAT")
      opt->check(FiniteNumber().description(""));
  }
  for (CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; })) applyTypeChecks(*sub);
}

}  // namespace st::app::cli

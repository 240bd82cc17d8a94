/// @file validators.hpp
/// Number checks for command-line options, in the project's words. CLI11 alone turns
/// `--runs -5` into a huge unsigned, lets `nan` and `inf` through its ranges, and prints
/// 309-digit bounds; these validators refuse such values before CLI11 converts them.
///
/// Use: `cmd->add_option("--runs", o.runs, "...")->check(cli::WholeNumber(1, 10'000'000));`
/// A validator's message states the rule and the value ("must be a whole number >= 1, got
/// -5"); CLI11 puts the option's name in front and app/cli/parse_errors.cpp joins the two as
/// the user typed the flag: "--runs must be a whole number >= 1, got -5".
///
/// Bounds at +-infinity (or beyond the double range) are "no bound" and never printed.
/// main also applies the type-wide checks (applyTypeChecks) to every option of every
/// command, so an option without its own check still refuses a negative unsigned and a
/// non-finite double.
#pragma once
#include <CLI/CLI.hpp>
#include <cstdint>
#include <limits>
#include <string>

namespace st::app::cli {

constexpr double kNoBound = std::numeric_limits<double>::infinity();
/// The 64-bit integer limits as exact bounds (long double holds every 64-bit integer).
constexpr long double kMaxU64 = static_cast<long double>(std::numeric_limits<uint64_t>::max());
constexpr long double kMinI64 = static_cast<long double>(std::numeric_limits<int64_t>::min());
constexpr long double kMaxI64 = static_cast<long double>(std::numeric_limits<int64_t>::max());

/// A whole number (decimal digits, optional sign) in [min, max]. Bounds are long double so
/// that every int64 and uint64 value is exact (seeds use the whole uint64 range).
CLI::Validator WholeNumber(long double min, long double max = kNoBound);

/// Whether a bound of a real-number check belongs to the allowed range.
enum class Bound { kClosed, kOpen };

/// A finite real number in the range from min to max (closed or open at each end).
/// Refuses nan, inf and text. Number(0, kNoBound, Bound::kOpen) is "a number > 0".
CLI::Validator Number(double min, double max, Bound min_bound = Bound::kClosed,
                      Bound max_bound = Bound::kClosed);

/// Any finite real number (the type-wide check of every FLOAT option).
CLI::Validator FiniteNumber();

/// Adds the type-wide checks to every option of `app` and its sub-commands, read from the
/// type CLI11 recorded for the option: UINT options refuse negative and non-whole values
/// (before CLI11 would wrap them), INT options non-whole values, FLOAT options nan, inf
/// and text. They add nothing to the help text. Call once, after every command is added.
void applyTypeChecks(CLI::App& app);

/// A number for a message: shortest %g form that reads back ("0.1", "1e+06", "-5").
std::string formatNumber(long double v);

}  // namespace st::app::cli

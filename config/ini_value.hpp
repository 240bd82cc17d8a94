/// @file ini_value.hpp
/// How one value type is read from and written to an .ini key (IniCodec<V>): the writing
/// form reads back to the same value (numbers in their shortest exact decimal form), so an
/// effective configuration printed by a schema loads again unchanged.
#pragma once
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "common/attitude.hpp"
#include "config/ini_reader.hpp"

namespace st {

/// The shortest decimal form of `v` that parses back to exactly `v` (up to 17 digits).
std::string formatIniNumber(double v);
/// Numbers separated by spaces (in brackets when `brackets`, the MRPT TCamera style).
std::string formatIniNumbers(const std::vector<double>& v, bool brackets = false);
/// Splits a comma-separated list, trimming spaces and dropping empty items.
std::vector<std::string> splitIniList(const std::string& text);

/// Whether the key counts as given: a key with an empty value is absent for numbers, but a
/// value of its own for strings and lists (an empty list, an empty label).
template <class V>
struct IniCodec;

template <>
struct IniCodec<double> {
  static bool present(const IniReader& r, const std::string& s, const std::string& k) { return r.has(s, k); }
  static void read(const IniReader& r, const std::string& s, const std::string& k, double& v) { v = r.num(s, k, v); }
  static std::string write(double v) { return formatIniNumber(v); }
};

template <>
struct IniCodec<int> {
  static bool present(const IniReader& r, const std::string& s, const std::string& k) { return r.has(s, k); }
  static void read(const IniReader& r, const std::string& s, const std::string& k, int& v) { v = r.integer(s, k, v); }
  static std::string write(int v) { return std::to_string(v); }
};

template <>
struct IniCodec<uint64_t> {
  static bool present(const IniReader& r, const std::string& s, const std::string& k) { return r.has(s, k); }
  static void read(const IniReader& r, const std::string& s, const std::string& k, uint64_t& v) { v = r.uint64(s, k, v); }
  static std::string write(uint64_t v) { return std::to_string(v); }
};

template <>
struct IniCodec<long> {
  static bool present(const IniReader& r, const std::string& s, const std::string& k) { return r.has(s, k); }
  /// Through a number, so that "2e6" is a count too; whole and below 2^53 (exact in a double).
  static void read(const IniReader& r, const std::string& s, const std::string& k, long& v);
  static std::string write(long v) { return std::to_string(v); }
};

/// Bit masks: a non-negative integer of 32 bits.
template <>
struct IniCodec<uint32_t> {
  static bool present(const IniReader& r, const std::string& s, const std::string& k) { return r.has(s, k); }
  static void read(const IniReader& r, const std::string& s, const std::string& k, uint32_t& v);
  static std::string write(uint32_t v) { return std::to_string(v); }
};

template <>
struct IniCodec<bool> {
  static bool present(const IniReader& r, const std::string& s, const std::string& k) { return r.has(s, k); }
  static void read(const IniReader& r, const std::string& s, const std::string& k, bool& v) { v = r.boolean(s, k, v); }
  static std::string write(bool v) { return v ? "true" : "false"; }
};

template <>
struct IniCodec<std::string> {
  static bool present(const IniReader& r, const std::string& s, const std::string& k) { return r.exists(s, k); }
  static void read(const IniReader& r, const std::string& s, const std::string& k, std::string& v) { v = r.str(s, k, ""); }
  static std::string write(const std::string& v) { return v; }
};

template <>
struct IniCodec<std::vector<double>> {
  static bool present(const IniReader& r, const std::string& s, const std::string& k) { return r.exists(s, k); }
  static void read(const IniReader& r, const std::string& s, const std::string& k, std::vector<double>& v) { v = r.numbers(s, k, v); }
  static std::string write(const std::vector<double>& v) { return formatIniNumbers(v, true); }
};

template <>
struct IniCodec<std::vector<std::string>> {
  static bool present(const IniReader& r, const std::string& s, const std::string& k) { return r.exists(s, k); }
  static void read(const IniReader& r, const std::string& s, const std::string& k, std::vector<std::string>& v) { v = splitIniList(r.str(s, k, "")); }
  static std::string write(const std::vector<std::string>& v);
};

/// Fixed-size vectors (x y [z]): exactly N numbers.
void readIniVector(const IniReader& r, const std::string& s, const std::string& k, double* out, int n);

template <>
struct IniCodec<Vec2> {
  static bool present(const IniReader& r, const std::string& s, const std::string& k) { return r.has(s, k); }
  static void read(const IniReader& r, const std::string& s, const std::string& k, Vec2& v) { readIniVector(r, s, k, v.data(), 2); }
  static std::string write(const Vec2& v) { return formatIniNumbers({v.x(), v.y()}); }
};

template <>
struct IniCodec<Vec3> {
  static bool present(const IniReader& r, const std::string& s, const std::string& k) { return r.has(s, k); }
  static void read(const IniReader& r, const std::string& s, const std::string& k, Vec3& v) { readIniVector(r, s, k, v.data(), 3); }
  static std::string write(const Vec3& v) { return formatIniNumbers({v.x(), v.y(), v.z()}); }
};

/// Intervals "t0 t1 [t0 t1 ...]": an even count of numbers.
template <>
struct IniCodec<std::vector<std::pair<double, double>>> {
  using Pairs = std::vector<std::pair<double, double>>;
  static bool present(const IniReader& r, const std::string& s, const std::string& k) { return r.exists(s, k); }
  static void read(const IniReader& r, const std::string& s, const std::string& k, Pairs& v);
  static std::string write(const Pairs& v);
};

}  // namespace st

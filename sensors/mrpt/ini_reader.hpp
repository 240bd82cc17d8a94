/// @file ini_reader.hpp
/// Strict reading of .ini keys through MRPT's CConfigFileBase: a key that is present must
/// parse completely, and onlyKeys() refuses unknown keys by name (a typo must not be
/// silently ignored). Defaults stay with the option structs: every reader is given the
/// current value and returns it when the key is absent.
#pragma once
#include <set>
#include <string>

namespace mrpt::config {
class CConfigFileBase;
}

namespace st {

struct IniReader {
  const mrpt::config::CConfigFileBase& cfg;
  std::string source;  ///< the file, for messages ("" when unknown)
  /// Messages say "section 'S' key 'K'" instead of "[S] K": MRPT's stacked exceptions
  /// (CGenericSensor::loadConfig wraps ours) cut a message at its first ']'.
  bool mrpt_safe = false;

  std::string where(const std::string& sec, const std::string& key) const;
  std::string where(const std::string& sec) const;
  bool has(const std::string& sec, const std::string& key) const;
  std::string str(const std::string& sec, const std::string& key, const std::string& def) const;
  double num(const std::string& sec, const std::string& key, double def) const;
  int integer(const std::string& sec, const std::string& key, int def) const;
  bool boolean(const std::string& sec, const std::string& key, bool def) const;
  /// Throws InputError naming the first key of `sec` that is not in `allowed`.
  void onlyKeys(const std::string& sec, const std::set<std::string>& allowed) const;
};

}  // namespace st

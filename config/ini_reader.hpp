/// @file ini_reader.hpp
/// Strict reading of .ini keys through MRPT's CConfigFileBase: a key that is present must
/// parse completely, and onlyKeys() refuses unknown keys by name, suggesting the nearest
/// known one (a typo must not be silently ignored). Defaults stay with the option structs:
/// every reader is given the current value and returns it when the key is absent.
/// Declarative schemas built on this reader: config/schema.hpp.
#pragma once
#include <mrpt/config/CConfigFile.h>  // openIniFile's caller destroys what it returns

#include <cstdint>
#include <memory>
#include <set>
#include <string>
#include <vector>

namespace st {

struct IniReader {
  const mrpt::config::CConfigFileBase& cfg;
  std::string source;  ///< the file, for messages ("" when unknown)
  /// Messages say "section 'S' key 'K'" instead of "[S] K": MRPT's stacked exceptions
  /// (CGenericSensor::loadConfig wraps ours) cut a message at its first ']'.
  bool mrpt_safe = false;

  std::string where(const std::string& sec, const std::string& key) const;
  std::string where(const std::string& sec) const;
  /// "file: [S] key 'K'" (or the MRPT-safe "file: section 'S' key 'K'").
  std::string whereKey(const std::string& sec, const std::string& key) const;
  bool has(const std::string& sec, const std::string& key) const;
  /// True when the key is written in the section, even with an empty value.
  bool exists(const std::string& sec, const std::string& key) const;
  std::string str(const std::string& sec, const std::string& key, const std::string& def) const;
  double num(const std::string& sec, const std::string& key, double def) const;
  int integer(const std::string& sec, const std::string& key, int def) const;
  uint64_t uint64(const std::string& sec, const std::string& key, uint64_t def) const;
  bool boolean(const std::string& sec, const std::string& key, bool def) const;
  /// A number list ("[640 480]", "1, 2, 3"); `def` when the key is absent.
  std::vector<double> numbers(const std::string& sec, const std::string& key,
                              const std::vector<double>& def) const;
  /// Throws InputError naming the first key of `sec` that is not in `allowed`, with the
  /// nearest allowed key as a suggestion when one is close (closestKey).
  void onlyKeys(const std::string& sec, const std::set<std::string>& allowed) const;
  /// Throws InputError naming the first section of the file that is not in `allowed`
  /// (a misspelt section must not turn into defaults), with the nearest allowed one as a
  /// suggestion; `kind` says what the file is ("a tracker file") for the list of sections.
  void onlySections(const std::set<std::string>& allowed, const std::string& kind) const;
};

/// Throws InputError naming `source`, the section and the key when a key is written twice in
/// one section of the .ini text (MRPT keeps the last one in silence).
void refuseDuplicateKeys(const std::string& text, const std::string& source);

/// Levenshtein distance (insertions, deletions, substitutions) between two keys.
int editDistance(const std::string& a, const std::string& b);
/// The candidate nearest to `key` by edit distance when it is close enough to be a typo of
/// it (distance <= 2, or <= a third of the key's length); "" otherwise.
std::string closestKey(const std::string& key, const std::vector<std::string>& candidates);

/// MRPT's reader of the .ini file `path` (a key written twice in a section is refused). Its preprocessor ($env{}, $eval{}, @define) throws
/// MRPT's own exception on bad syntax (found by fuzzing): here an InputError naming the file.
std::unique_ptr<mrpt::config::CConfigFile> openIniFile(const std::string& path);

}  // namespace st

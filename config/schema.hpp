/// @file schema.hpp
/// A declarative schema of one .ini section: a table of keys bound to members of a struct
/// (the defaults are the struct's own member initialisers), each with a one-line help.
/// From one table come strict reading (unknown keys are InputErrors naming the file,
/// section and key with the nearest valid key; bad values name the key; required keys) and
/// the printing of the effective configuration in ini form, which reads back to the same
/// values.
///
///   struct GyroKeys { double rate_hz = 0; double arw_deg_rt_h = 0; std::string mode = "a"; };
///   const SectionSchema<GyroKeys>& gyroSchema() {
///     static const auto s = SectionSchema<GyroKeys>()
///         .add("rate_hz", &GyroKeys::rate_hz, "[Hz] sample rate").required()
///         .add("arw_deg_rt_h", &GyroKeys::arw_deg_rt_h, "[deg/sqrt(h)] angle random walk")
///         .choice("mode", &GyroKeys::mode, {"a", "b"}, "which model");
///     return s;
///   }
///   GyroKeys g;                                            // defaults
///   gyroSchema().read(IniReader{cfg, path}, "gyro", g);   // strict
///   std::string text = gyroSchema().print("gyro", g);    // "[gyro]\n# [Hz] ...\nrate_hz = 100\n..."
#pragma once
#include <functional>
#include <stdexcept>
#include <type_traits>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "common/errors.hpp"
#include "config/ini_reader.hpp"
#include "config/ini_value.hpp"

namespace st {

/// Prints one key with its help as a comment line above it (MRPT's ini parser takes only
/// whole-line comments).
std::string formatIniKey(const std::string& key, const std::string& value, const std::string& help);
/// Throws the InputError for a value of `key` outside `names`, suggesting the nearest name.
/// `shown` with the fewest digits (6..17) whose conversion `to` gives `stored` back exactly
/// (%.17g when none does).
std::string formatIniNumberThrough(double shown, double stored,
                                   const std::function<double(const double&)>& to);

[[noreturn]] void throwBadChoice(const IniReader& r, const std::string& sec, const std::string& key,
                                 const std::string& value, const std::vector<std::string>& names);

/// Throws the InputError for the first old key name of `renamed` written in `sec`, naming
/// its new name.
void refuseRenamedKeys(const IniReader& r, const std::string& sec,
                       const std::vector<std::pair<std::string, std::string>>& renamed);

template <class T>
class SectionSchema {
 public:
  struct Key {
    std::string name, help;
    bool required = false;
    bool printed = true;  ///< false for read-only aliases (another unit of a printed key)
    std::function<bool(const IniReader&, const std::string&)> present;
    std::function<void(const IniReader&, const std::string&, T&)> read;
    std::function<std::string(const T&)> write;
    std::function<double(const T&)> number;  ///< a numeric member's value (range())
    /// The value as written in the file, for range() and its message (a converted key's
    /// member is in another unit: its value converted back is not the text's digits).
    std::function<double(const IniReader&, const std::string&)> written;
  };

  /// A key bound to a member of type double, int, uint64_t, bool, std::string, number or
  /// string lists, Vec2, Vec3 or intervals (ini_value.hpp).
  template <class V>
  SectionSchema& add(const std::string& key, V T::*member, const std::string& help) {
    Key k;
    k.name = key;
    k.help = help;
    k.present = [key](const IniReader& r, const std::string& s) { return IniCodec<V>::present(r, s, key); };
    k.read = [key, member](const IniReader& r, const std::string& s, T& t) {
      IniCodec<V>::read(r, s, key, t.*member);
    };
    k.write = [member](const T& t) { return IniCodec<V>::write(t.*member); };
    if constexpr (std::is_arithmetic_v<V> && !std::is_same_v<V, bool>)
      k.number = [member](const T& t) { return static_cast<double>(t.*member); };
    keys_.push_back(std::move(k));
    return *this;
  }

  /// Bounds the last key added (a number) to [lo, hi], stated in its help: a value outside is
  /// an InputError naming the key and the range, before any work (issue 39: `rate_hz =
  /// 2147483647` filled the disk, filter noise 3.4e38 and biases 1e308 were taken).
  SectionSchema& range(double lo, double hi) {
    Key& k = keys_.back();
    if (!k.number) throw std::logic_error("range() on the non-numeric key " + k.name);
    // No brackets: MRPT cuts a sensor's error message at its first ']' (IniReader::mrpt_safe).
    const std::string span = "from " + IniCodec<double>::write(lo) + " to " + IniCodec<double>::write(hi);
    k.help += " (" + span + ")";
    k.read = [plain = k.read, number = k.number, written = k.written, key = k.name, lo, hi, span](
                 const IniReader& r, const std::string& s, T& t) {
      plain(r, s, t);
      const double v = written ? written(r, s) : number(t);
      if (!(v >= lo && v <= hi))
        throw InputError(r.whereKey(s, key) + " = " + IniCodec<double>::write(v) +
                         ": must be " + span);
    };
    return *this;
  }

  /// A string member restricted to `names` (a value outside is an error with a suggestion).
  SectionSchema& choice(const std::string& key, std::string T::*member,
                        std::vector<std::string> names, const std::string& help) {
    add(key, member, help + " (" + join(names, " | ") + ")");
    auto plain = keys_.back().read;
    keys_.back().read = [key, member, names, plain](const IniReader& r, const std::string& s, T& t) {
      plain(r, s, t);
      for (const auto& n : names)
        if (t.*member == n) return;
      throwBadChoice(r, s, key, t.*member, names);
    };
    return *this;
  }

  /// Another unit of a printed double key: read as value * scale into the member, never
  /// printed (the printed configuration uses the canonical key).
  SectionSchema& alias(const std::string& key, double T::*member, double scale,
                       const std::string& help) {
    add(key, member, help);
    keys_.back().read = [key, member, scale](const IniReader& r, const std::string& s, T& t) {
      t.*member = scale * r.num(s, key, 0.0);
    };
    keys_.back().printed = false;
    return *this;
  }

  /// A key in its own unit bound to a member in another (datasheet deg/sqrt(h) into the
  /// filter's rad/sqrt(s), yaw-pitch-roll degrees into a rotation matrix): read as V, stored
  /// as `to(v)`; printed as `from(member)`, and for numbers with the fewest digits whose
  /// conversion gives the member back exactly (so the printed file reads back to the same
  /// filter). range() after it bounds the value in the key's unit.
  template <class V, class M>
  SectionSchema& converted(const std::string& key, M T::*member, std::function<M(const V&)> to,
                           std::function<V(const M&)> from, const std::string& help) {
    Key k;
    k.name = key;
    k.help = help;
    k.present = [key](const IniReader& r, const std::string& s) { return IniCodec<V>::present(r, s, key); };
    k.read = [key, member, to, from](const IniReader& r, const std::string& s, T& t) {
      V v = from(t.*member);
      IniCodec<V>::read(r, s, key, v);
      t.*member = to(v);
    };
    k.write = [member, to, from](const T& t) {
      if constexpr (std::is_same_v<V, double> && std::is_same_v<M, double>)
        return formatIniNumberThrough(from(t.*member), t.*member, to);
      else
        return IniCodec<V>::write(from(t.*member));
    };
    if constexpr (std::is_arithmetic_v<V> && !std::is_same_v<V, bool>) {
      k.number = [member, from](const T& t) { return static_cast<double>(from(t.*member)); };
      k.written = [key](const IniReader& r, const std::string& s) {
        V v{};
        IniCodec<V>::read(r, s, key, v);
        return static_cast<double>(v);
      };
    }
    keys_.push_back(std::move(k));
    return *this;
  }

  /// A string key naming an enum member's values (`names`: the key's text -> the value);
  /// another text is an error with a suggestion.
  template <class E>
  SectionSchema& mapped(const std::string& key, E T::*member,
                        std::vector<std::pair<std::string, E>> names, const std::string& help) {
    std::vector<std::string> texts;
    for (const auto& [text, value] : names) texts.push_back(text);
    Key k;
    k.name = key;
    k.help = help + " (" + join(texts, " | ") + ")";
    k.present = [key](const IniReader& r, const std::string& s) { return IniCodec<std::string>::present(r, s, key); };
    k.read = [key, member, names, texts](const IniReader& r, const std::string& s, T& t) {
      std::string v;
      IniCodec<std::string>::read(r, s, key, v);
      for (const auto& [text, value] : names)
        if (v == text) {
          t.*member = value;
          return;
        }
      throwBadChoice(r, s, key, v, texts);
    };
    k.write = [member, names](const T& t) {
      for (const auto& [text, value] : names)
        if (t.*member == value) return text;
      throw std::logic_error("a mapped key's member holds a value without a name");
    };
    keys_.push_back(std::move(k));
    return *this;
  }

  /// An old name of `new_key`: present in a section, it is refused naming the new key (a
  /// renamed key must never be silently ignored, nor silently accepted). A key split in two
  /// names both, separated by a space.
  SectionSchema& renamed(const std::string& old_key, const std::string& new_key) {
    renamed_.emplace_back(old_key, new_key);
    return *this;
  }

  /// Marks the last key added as required (absent -> InputError naming it).
  SectionSchema& required() {
    keys_.back().required = true;
    return *this;
  }

  /// Every key of `inner`, bound to the member `part` of T (one section made of two structs).
  template <class U>
  SectionSchema& include(const SectionSchema<U>& inner, U T::*part) {
    for (const auto& ik : inner.keys()) {
      Key k;
      k.name = ik.name;
      k.help = ik.help;
      k.required = ik.required;
      k.printed = ik.printed;
      k.present = ik.present;
      auto rd = ik.read;
      auto wr = ik.write;
      k.read = [rd, part](const IniReader& r, const std::string& s, T& t) { rd(r, s, t.*part); };
      k.write = [wr, part](const T& t) { return wr(t.*part); };
      if (ik.number) k.number = [nb = ik.number, part](const T& t) { return nb(t.*part); };
      k.written = ik.written;
      keys_.push_back(std::move(k));
    }
    renamed_.insert(renamed_.end(), inner.renamedKeys().begin(), inner.renamedKeys().end());
    return *this;
  }

  const std::vector<Key>& keys() const { return keys_; }
  const std::vector<std::pair<std::string, std::string>>& renamedKeys() const { return renamed_; }
  std::set<std::string> names() const {
    std::set<std::string> out;
    for (const auto& k : keys_) out.insert(k.name);
    return out;
  }

  /// Strict read of section `sec` into `out` (keys absent keep out's values). Unknown keys,
  /// missing required keys and unparsable values throw InputError naming file/section/key.
  void read(const IniReader& r, const std::string& sec, T& out) const {
    refuseRenamedKeys(r, sec, renamed_);  // before onlyKeys: the message names the new key
    r.onlyKeys(sec, names());
    readKnown(r, sec, out);
  }

  /// read() without the unknown-key check, for a section shared with another reader that
  /// checks its own keys (old names are still refused).
  void readKnown(const IniReader& r, const std::string& sec, T& out) const {
    refuseRenamedKeys(r, sec, renamed_);
    for (const auto& k : keys_) {
      if (k.present(r, sec))
        k.read(r, sec, out);
      else if (k.required)
        throw InputError(r.whereKey(sec, k.name) + ": missing key (" + k.help + ")");
    }
  }

  /// The section in ini form, every printed key with its value and help.
  std::string print(const std::string& sec, const T& v) const {
    std::string s = "[" + sec + "]\n";
    for (const auto& k : keys_)
      if (k.printed) s += formatIniKey(k.name, k.write(v), k.help);
    return s;
  }

 private:
  static std::string join(const std::vector<std::string>& v, const char* sep) {
    std::string s;
    for (const auto& x : v) s += (s.empty() ? "" : sep) + x;
    return s;
  }

  std::vector<Key> keys_;
  std::vector<std::pair<std::string, std::string>> renamed_;  ///< old name -> new name
};

}  // namespace st

/// @file printer_registry.hpp
/// The schemas `startracker config FILE` knows: each entry recognises the sections of a
/// file that it owns and prints their effective configuration (every default filled in, in
/// ini form that reads back). A schema is added with one call, e.g. in app/config_schemas.cpp:
///
///   printers.add("tracker", sectionNamed("filter"), perSection(&printTrackerFilter));
///
/// where `std::string printTrackerFilter(const IniReader& r, const std::string& sec)` reads
/// the section strictly with its SectionSchema and returns schema.print(sec, value).
///
/// Entries are tried in the order they were added; a section claimed by an earlier entry is
/// not offered to a later one.
#pragma once
#include <functional>
#include <string>
#include <vector>

#include "config/ini_reader.hpp"

namespace st {

struct SchemaPrinter {
  std::string name;  ///< e.g. "scenario", for messages and --help
  /// The sections of the file this schema owns, in print order (empty: not this schema).
  /// `wanted` is the user's --section ("" = any).
  std::function<std::vector<std::string>(const IniReader& r, const std::string& wanted)> find;
  /// Strict read of the owned sections (those `find` gave and no earlier schema claimed),
  /// then their effective configuration in ini form.
  std::function<std::string(const IniReader& r, const std::vector<std::string>& sections)> print;
};

/// print: one section at a time, concatenated.
decltype(SchemaPrinter::print) perSection(
    std::function<std::string(const IniReader& r, const std::string& section)> print_one);

/// find: the file has section `sec` (the schema owns exactly that one).
std::function<std::vector<std::string>(const IniReader&, const std::string&)> sectionNamed(
    const std::string& sec);

class SchemaPrinters {
 public:
  void add(SchemaPrinter p) { printers_.push_back(std::move(p)); }
  void add(const std::string& name, decltype(SchemaPrinter::find) find,
           decltype(SchemaPrinter::print) print) {
    add(SchemaPrinter{name, std::move(find), std::move(print)});
  }
  const std::vector<SchemaPrinter>& all() const { return printers_; }

  /// The effective configuration of every recognised schema of the file (or only section
  /// `wanted`), followed by a comment naming the sections no schema owns. InputError when
  /// nothing is recognised.
  std::string print(const IniReader& r, const std::string& wanted = "") const;

 private:
  std::vector<SchemaPrinter> printers_;
};

}  // namespace st

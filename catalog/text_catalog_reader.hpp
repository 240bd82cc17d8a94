/// @file text_catalog_reader.hpp
/// What the '|'-separated text catalogs (Hipparcos hip_main.dat, Tycho-2 tyc2.dat) share:
/// a line reader for plain or gzip files (by content, so a renamed file still reads), the
/// split of a line into fields, and number parsing whose errors name file, line and field.
/// Internal to catalog/.
#pragma once
#include <zlib.h>

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

namespace st::catalog_detail {

/// Lines of a plain or gzip text file (concatenated gzip members read as one stream).
class GzLineReader {
 public:
  /// `what` names the file's format in the cannot-open message.
  GzLineReader(const std::string& path, const std::string& what);
  ~GzLineReader();
  GzLineReader(const GzLineReader&) = delete;
  GzLineReader& operator=(const GzLineReader&) = delete;

  /// Next line without its line ending; false at the end. Throws InputError on a read error
  /// (e.g. a truncated gzip stream).
  bool next(std::string& line);
  std::size_t lineNumber() const { return lines_; }

 private:
  std::string path_;
  gzFile f_ = nullptr;
  std::size_t lines_ = 0;
};

/// One line split at '|', fields trimmed of blanks, for error messages that name the place.
class PipeFields {
 public:
  PipeFields(const std::string& path, std::size_t line_number, const std::string& line);
  std::size_t size() const { return fields_.size(); }
  const std::string& operator[](std::size_t k) const { return fields_[k]; }
  /// "path:line" for messages.
  std::string place() const;
  /// "path:line: field NAME" for messages.
  std::string where(const std::string& field_name) const;
  /// The field as a number; an empty field gives `empty_value`; anything that is not one
  /// complete finite number throws InputError naming file, line, field and text.
  double number(std::size_t k, const std::string& field_name, double empty_value) const;

 private:
  const std::string& path_;
  std::size_t line_;
  std::vector<std::string> fields_;
};

/// Whether the line holds nothing but blanks.
bool isBlank(const std::string& line);

/// Calls `record` with every line of a '|'-separated catalog file (plain or gzip) that is not
/// blank, split into fields; `what` names the catalog in messages ("Tycho-2 catalog").
void forEachPipeRecord(const std::string& path, const std::string& what,
                       const std::function<void(const PipeFields&)>& record);

}  // namespace st::catalog_detail

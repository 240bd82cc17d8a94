#include "catalog/text_catalog_reader.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>

#include "common/errors.hpp"

namespace st::catalog_detail {
namespace {

std::string trim(const std::string& s, std::size_t b, std::size_t e) {
  while (b < e && (s[b] == ' ' || s[b] == '\t')) ++b;
  while (e > b && (s[e - 1] == ' ' || s[e - 1] == '\t' || s[e - 1] == '\r')) --e;
  return s.substr(b, e - b);
}

}  // namespace

GzLineReader::GzLineReader(const std::string& path, const std::string& what) : path_(path) {
  f_ = gzopen(path.c_str(), "rb");  // reads plain files transparently
  if (!f_) throw InputError(path + ": cannot open " + what + " file");
  gzbuffer(f_, 1 << 17);
}

GzLineReader::~GzLineReader() {
  if (f_) gzclose(f_);
}

bool GzLineReader::next(std::string& line) {
  line.clear();
  char buf[4096];
  while (gzgets(f_, buf, sizeof buf)) {
    line += buf;
    if (!line.empty() && line.back() == '\n') {
      line.pop_back();
      if (!line.empty() && line.back() == '\r') line.pop_back();
      ++lines_;
      return true;
    }
  }
  int err = Z_OK;
  const char* msg = gzerror(f_, &err);
  if (err != Z_OK && err != Z_STREAM_END)
    throw InputError(path_ + ": read error after line " + std::to_string(lines_) + ": " +
                     (msg ? msg : "unknown zlib error") + " (truncated or corrupt file?)");
  if (line.empty()) return false;
  ++lines_;
  return true;
}

PipeFields::PipeFields(const std::string& path, std::size_t line_number, const std::string& line)
    : path_(path), line_(line_number) {
  std::size_t b = 0;
  for (std::size_t i = 0; i <= line.size(); ++i)
    if (i == line.size() || line[i] == '|') {
      fields_.push_back(trim(line, b, i));
      b = i + 1;
    }
}

std::string PipeFields::place() const { return path_ + ":" + std::to_string(line_); }

std::string PipeFields::where(const std::string& field_name) const {
  return path_ + ":" + std::to_string(line_) + ": field " + field_name;
}

double PipeFields::number(std::size_t k, const std::string& field_name, double empty_value) const {
  const std::string& f = fields_.at(k);
  if (f.empty()) return empty_value;
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(f.c_str(), &end);
  if (end == f.c_str() || *end != '\0' || errno == ERANGE || !std::isfinite(v))
    throw InputError(where(field_name) + ": '" + f + "' is not a number");
  return v;
}

bool isBlank(const std::string& line) {
  for (char c : line)
    if (c != ' ' && c != '\t' && c != '\r') return false;
  return true;
}

void forEachPipeRecord(const std::string& path, const std::string& what,
                       const std::function<void(const PipeFields&)>& record) {
  GzLineReader reader(path, what);
  std::string line;
  while (reader.next(line))
    if (!isBlank(line)) record(PipeFields(path, reader.lineNumber(), line));
}

}  // namespace st::catalog_detail

#include "common/output_file.hpp"
#include "app/montecarlo/csv.hpp"

#include <fstream>
#include <sstream>

#include "common/errors.hpp"

namespace st::app::mc {
namespace {

std::string csvCell(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

void writeLine(std::ostream& f, const Row& r) {
  for (std::size_t i = 0; i < r.size(); ++i) f << (i ? "," : "") << csvCell(r[i]);
  f << "\n";
}

bool splitLine(const std::string& line, Row& out) {
  out.clear();
  std::string cell;
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
        cell += '"';
        ++i;
      } else if (c == '"') {
        quoted = false;
      } else {
        cell += c;
      }
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      out.push_back(cell);
      cell.clear();
    } else if (c != '\r') {
      cell += c;
    }
  }
  out.push_back(cell);
  return !quoted;
}

}  // namespace

void writeCsv(const Table& t, const std::string& path) {
  std::ostringstream f;
  writeLine(f, t.columns);
  for (const Row& r : t.rows) writeLine(f, r);
  writeFileAtomically(path, f.str());
}

Table readCsv(const std::string& path) {
  std::ifstream f(path);
  if (!f) throw InputError("cannot read '" + path + "'");
  Table t;
  std::string line;
  std::size_t n = 0;
  Row row;
  while (std::getline(f, line)) {
    ++n;
    if (!splitLine(line, row))
      throw InputError(path + ":" + std::to_string(n) + ": unterminated quoted cell");
    if (n == 1) {
      t.columns = row;
      continue;
    }
    if (line.empty()) continue;
    if (row.size() != t.columns.size())
      throw InputError(path + ":" + std::to_string(n) + ": " + std::to_string(row.size()) +
                       " cells, header has " + std::to_string(t.columns.size()));
    t.rows.push_back(row);
  }
  if (n == 0) throw InputError("'" + path + "' is empty (no CSV header)");
  return t;
}

std::string toMarkdown(const Table& t) {
  std::ostringstream s;
  s << "|";
  for (const auto& c : t.columns) s << " " << c << " |";
  s << "\n|";
  for (std::size_t i = 0; i < t.columns.size(); ++i) s << "---|";
  s << "\n";
  for (const Row& r : t.rows) {
    s << "|";
    for (const auto& c : r) s << " " << c << " |";
    s << "\n";
  }
  return s.str();
}

}  // namespace st::app::mc

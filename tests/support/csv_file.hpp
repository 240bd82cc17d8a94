// Reading the CSV files the commands write (replay/live trajectories, Monte Carlo tables):
// one splitter for every test. Plain comma-separated cells, no quoting (none is written).
#pragma once
#include <algorithm>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace st::test {

inline std::vector<std::string> splitCsvLine(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream ss(line);
  for (std::string c; std::getline(ss, c, ',');) cells.push_back(c);
  return cells;
}

/// Every line as cells, the header first (an unreadable file gives no rows).
inline std::vector<std::vector<std::string>> readCsvCells(const std::string& path) {
  std::ifstream f(path);
  std::vector<std::vector<std::string>> rows;
  for (std::string line; std::getline(f, line);) rows.push_back(splitCsvLine(line));
  return rows;
}

/// The rows after the header as fields by column name.
inline std::vector<std::map<std::string, std::string>> readCsvRows(const std::string& path) {
  const auto cells = readCsvCells(path);
  std::vector<std::map<std::string, std::string>> rows;
  for (std::size_t k = 1; k < cells.size(); ++k) {
    std::map<std::string, std::string> r;
    for (std::size_t i = 0; i < cells[0].size() && i < cells[k].size(); ++i)
      r[cells[0][i]] = cells[k][i];
    rows.push_back(r);
  }
  return rows;
}

/// Column `name` as numbers, for rows whose column `filter` is 1, skipping the first `skip`
/// of those rows (rows of another width are skipped).
inline std::vector<double> csvColumn(const std::string& path, const std::string& name,
                                     const std::string& filter, std::size_t skip) {
  const auto cells = readCsvCells(path);
  std::vector<double> v;
  if (cells.empty()) return v;
  const auto& head = cells[0];
  const std::size_t c = std::size_t(std::find(head.begin(), head.end(), name) - head.begin());
  const std::size_t cf = std::size_t(std::find(head.begin(), head.end(), filter) - head.begin());
  std::size_t seen = 0;
  for (std::size_t k = 1; k < cells.size(); ++k) {
    const auto& f = cells[k];
    if (f.size() != head.size() || f[cf] != "1") continue;
    if (seen++ >= skip) v.push_back(std::stod(f[c]));
  }
  return v;
}

}  // namespace st::test

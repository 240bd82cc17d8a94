#include "solve/star_list.hpp"

#include "imageio/fits.hpp"


#include <algorithm>
#include <cctype>
#include <fstream>
#include <sstream>

#include "imageio/image_file.hpp"
#include "common/errors.hpp"

namespace st::solve {
namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
  return s;
}

bool endsWith(const std::string& s, const std::string& e) {
  return s.size() >= e.size() && s.compare(s.size() - e.size(), e.size(), e) == 0;
}

std::vector<std::string> splitCsv(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream ss(line);
  std::string cell;
  while (std::getline(ss, cell, ',')) {
    const auto b = cell.find_first_not_of(" \t\r");
    const auto e = cell.find_last_not_of(" \t\r");
    out.push_back(b == std::string::npos ? "" : cell.substr(b, e - b + 1));
  }
  return out;
}

double number(const std::string& path, int line, const std::string& column,
              const std::string& text) {
  try {
    std::size_t used = 0;
    const double v = std::stod(text, &used);
    if (used == text.size() && std::isfinite(v)) return v;
  } catch (const std::exception&) {
  }
  throw InputError(path + ":" + std::to_string(line) + ": column " + column + ": '" + text +
                   "' is not a number");
}

StarList loadCsv(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot read the star list");
  std::string line;
  if (!std::getline(in, line)) throw InputError(path + ": empty star list (a header line x,y,flux)");
  const std::vector<std::string> header = splitCsv(line);
  int ix = -1, iy = -1, iflux = -1;
  for (int i = 0; i < int(header.size()); ++i) {
    const std::string h = lower(header[i]);
    if (h == "x") ix = i;
    if (h == "y") iy = i;
    if (h == "flux") iflux = i;
  }
  if (ix < 0 || iy < 0)
    throw InputError(path + ":1: the header must name the columns x and y (and flux), got '" +
                     line + "'");
  StarList out;
  for (int n = 2; std::getline(in, line); ++n) {
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    const std::vector<std::string> cells = splitCsv(line);
    if (int(cells.size()) < int(header.size()))
      throw InputError(path + ":" + std::to_string(n) + ": " + std::to_string(cells.size()) +
                       " columns, the header has " + std::to_string(header.size()));
    Centroid c;
    c.px = Vec2(number(path, n, "x", cells[ix]), number(path, n, "y", cells[iy]));
    c.flux = iflux >= 0 ? number(path, n, "flux", cells[iflux]) : 0;
    out.stars.push_back(c);
  }
  return out;
}

class FitsTable {
 public:
  explicit FitsTable(const std::string& path) : path_(path) {
    if (fits_open_table(&f_, path.c_str(), READONLY, &status_))
      fail("cannot open a FITS binary table");
  }
  ~FitsTable() {
    int s = 0;
    if (f_) fits_close_file(f_, &s);
  }
  FitsTable(const FitsTable&) = delete;
  FitsTable& operator=(const FitsTable&) = delete;

  [[noreturn]] void fail(const std::string& what) {
    char msg[FLEN_STATUS] = {0};
    fits_get_errstatus(status_, msg);
    throw InputError(path_ + ": " + what + " (cfitsio: " + msg + ")");
  }
  long rows() {
    long n = 0;
    if (fits_get_num_rows(f_, &n, &status_)) fail("cannot count the rows");
    return n;
  }
  /// Column `name` (case-insensitive) as doubles; empty when absent and `!required`.
  std::vector<double> column(const char* name, bool required) {
    int col = 0;
    char templ[FLEN_VALUE];
    std::snprintf(templ, sizeof templ, "%s", name);
    if (fits_get_colnum(f_, CASEINSEN, templ, &col, &status_)) {
      if (!required) {
        status_ = 0;
        return {};
      }
      fail(std::string("no column ") + name + " (a star list needs X, Y and FLUX)");
    }
    std::vector<double> v(static_cast<std::size_t>(rows()));
    int anynul = 0;
    if (!v.empty() &&
        fits_read_col(f_, TDOUBLE, col, 1, 1, long(v.size()), nullptr, v.data(), &anynul, &status_))
      fail(std::string("cannot read column ") + name);
    return v;
  }
  std::optional<long> intKey(const char* key) {
    long v = 0;
    int s = 0;
    if (fits_read_key(f_, TLONG, key, &v, nullptr, &s)) return std::nullopt;
    return v;
  }
  std::optional<std::string> stringKey(const char* key) {
    char v[FLEN_VALUE] = {0};
    int s = 0;
    if (fits_read_key(f_, TSTRING, key, v, nullptr, &s)) return std::nullopt;
    return std::string(v);
  }

 private:
  std::string path_;
  fitsfile* f_ = nullptr;
  int status_ = 0;
};

StarList loadFitsTable(const std::string& path) {
  FitsTable t(path);
  const std::vector<double> x = t.column("X", true), y = t.column("Y", true),
                            flux = t.column("FLUX", false);
  StarList out;
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (!std::isfinite(x[i]) || !std::isfinite(y[i]))
      throw InputError(path + ": row " + std::to_string(i + 1) + ": X or Y is not finite");
    Centroid c;
    c.px = Vec2(x[i] - 1, y[i] - 1);  // FITS pixels are 1-based
    c.flux = flux.empty() ? 0 : flux[i];
    out.stars.push_back(c);
  }
  out.width = int(t.intKey("IMAGEW").value_or(0));
  out.height = int(t.intKey("IMAGEH").value_or(0));
  if (const auto date = t.stringKey("DATE-OBS")) {
    out.epoch_jyear = imageio::parseIsoEpoch(*date);
    if (out.epoch_jyear) out.epoch_source = "DATE-OBS";
  }
  return out;
}

/// A FITS file with an empty primary HDU followed by a binary table.
bool isFitsTable(const std::string& path) {
  fitsfile* f = nullptr;
  int status = 0, naxis = 0, type = 0;
  if (fits_open_file(&f, path.c_str(), READONLY, &status)) return false;
  fits_get_img_dim(f, &naxis, &status);
  const bool empty_primary = status == 0 && naxis == 0;
  fits_movabs_hdu(f, 2, &type, &status);
  const bool table = empty_primary && status == 0 && type == BINARY_TBL;
  int s = 0;
  fits_close_file(f, &s);
  return table;
}

}  // namespace

bool isStarList(const std::string& path) {
  const std::string p = lower(path);
  if (endsWith(p, ".csv") || endsWith(p, ".xyls") || endsWith(p, ".axy")) return true;
  return imageio::isFitsPath(path) && isFitsTable(path);
}

StarList loadStarList(const std::string& path) {
  StarList out = endsWith(lower(path), ".csv") ? loadCsv(path) : loadFitsTable(path);
  std::stable_sort(out.stars.begin(), out.stars.end(),
                   [](const Centroid& a, const Centroid& b) { return a.flux > b.flux; });
  if (!out.epoch_jyear) {
    out.epoch_jyear = imageio::parseIsoEpoch(path.substr(path.find_last_of('/') + 1));
    if (out.epoch_jyear) out.epoch_source = "file name";
  }
  return out;
}

}  // namespace st::solve

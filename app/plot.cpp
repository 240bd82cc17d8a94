#include "app/plot.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <mutex>
#include <optional>
#include <sstream>

#include "common/errors.hpp"

namespace st::app {
namespace {

std::string shellQuote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

/// A gnuplot double-quoted string literal.
std::string gpString(const std::string& s) {
  std::string q = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') q += '\\';
    q += c;
  }
  return q + "\"";
}

bool isExecutable(const std::string& path) { return access(path.c_str(), X_OK) == 0; }

/// The program's full path if it can be found (a path is checked as is; a bare name on PATH).
std::optional<std::string> findProgram(const std::string& program) {
  if (program.find('/') != std::string::npos)
    return isExecutable(program) ? std::optional<std::string>(program) : std::nullopt;
  const char* path = std::getenv("PATH");
  std::stringstream ss(path ? path : "/usr/bin:/bin");
  std::string dir;
  while (std::getline(ss, dir, ':')) {
    const std::string full = (dir.empty() ? "." : dir) + "/" + program;
    if (isExecutable(full)) return full;
  }
  return std::nullopt;
}

/// Runs a shell command; returns its exit status (-1 if it could not start) and its output.
int runCapture(const std::string& cmd, std::string& output) {
  output.clear();
  FILE* p = popen((cmd + " 2>&1").c_str(), "r");
  if (!p) return -1;
  char buf[4096];
  std::size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, p)) > 0) output.append(buf, n);
  const int st = pclose(p);
  return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

/// Whether gnuplot's `set terminal` listing has a line whose first word is `name`.
bool hasTerminal(const std::string& listing, const std::string& name) {
  std::istringstream in(listing);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream words(line);
    std::string first;
    if (words >> first && first == name) return true;
  }
  return false;
}

struct Probe {
  std::string problem;
  std::string terminal;
};

/// Finds the program and its PNG terminal once per program (cached: it costs a process).
Probe probe(const std::string& program) {
  static std::mutex mu;
  static std::map<std::string, Probe> cache;
  std::lock_guard<std::mutex> lock(mu);
  auto it = cache.find(program);
  if (it != cache.end()) return it->second;
  Probe pr;
  const auto full = findProgram(program);
  if (!full) {
    pr.problem = "gnuplot not found ('" + program +
                 "'): install the Debian package gnuplot-nox, or point ST_GNUPLOT / --gnuplot "
                 "at a gnuplot binary";
  } else {
    std::string out;
    const int rc = runCapture(shellQuote(*full) + " -e 'set terminal'", out);
    if (rc != 0) {
      pr.problem = "'" + *full + "' does not run as gnuplot (exit " + std::to_string(rc) +
                   "): " + out.substr(0, 200);
    } else if (hasTerminal(out, "pngcairo")) {
      pr.terminal = "pngcairo";
    } else if (hasTerminal(out, "png")) {
      pr.terminal = "png";
    } else {
      pr.problem = "'" + *full + "' has no PNG terminal (pngcairo or png); install gnuplot-nox";
    }
  }
  cache[program] = pr;
  return pr;
}

const char* kPalette[] = {"#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd",
                          "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22", "#17becf"};

std::string num(double v) {
  if (!std::isfinite(v)) return "NaN";
  char b[32];
  std::snprintf(b, sizeof b, "%.10g", v);
  return b;
}

}  // namespace

Plot makePlot(std::string title, std::string xlabel, std::string ylabel) {
  Plot p;
  p.title = std::move(title);
  p.xlabel = std::move(xlabel);
  p.ylabel = std::move(ylabel);
  return p;
}

std::string gnuplotProgram(const std::string& override_path) {
  if (!override_path.empty()) return override_path;
  const char* env = std::getenv("ST_GNUPLOT");
  if (env && *env) return env;
  return "gnuplot";
}

std::string gnuplotProblem(const std::string& program) { return probe(program).problem; }

std::string gnuplotScript(const Plot& p, const std::string& png_path, const std::string& terminal) {
  std::ostringstream s;
  s << "# gnuplot script written by startracker; run `gnuplot <this file>` to redraw\n";
  s << "set terminal " << terminal << " size " << p.width_px << "," << p.height_px
    << (terminal == "pngcairo" ? " font 'sans,10'" : "") << " noenhanced\n";
  s << "set output " << gpString(png_path) << "\n";
  s << "set title " << gpString(p.title) << "\n";
  s << "set xlabel " << gpString(p.xlabel) << "\nset ylabel " << gpString(p.ylabel) << "\n";
  s << "set grid\n";
  s << (p.key == "off" ? std::string("unset key\n") : "set key " + p.key + "\n");
  if (p.log_x) s << "set logscale x\n";
  if (p.log_y) s << "set logscale y\n";
  auto range = [&](const char* ax, const std::optional<double>& lo, const std::optional<double>& hi) {
    if (lo || hi)
      s << "set " << ax << "range [" << (lo ? num(*lo) : "*") << ":" << (hi ? num(*hi) : "*")
        << "]\n";
  };
  range("x", p.x_min, p.x_max);
  range("y", p.y_min, p.y_max);
  s << "set style fill solid 0.5 border -1\nset boxwidth 0.9 relative\n";

  // Data blocks, one per series: x y lo hi.
  std::vector<std::string> clauses;
  for (std::size_t i = 0; i < p.series.size(); ++i) {
    const PlotSeries& ser = p.series[i];
    const bool ranged = ser.style == PlotStyle::ErrorBars || ser.style == PlotStyle::Band;
    s << "$s" << i << " << EOD\n";
    for (std::size_t k = 0; k < ser.x.size(); ++k) {
      const double x = ser.x[k];
      const double y = k < ser.y.size() ? ser.y[k] : NAN;
      const double lo = k < ser.y_lo.size() ? ser.y_lo[k] : NAN;
      const double hi = k < ser.y_hi.size() ? ser.y_hi[k] : NAN;
      if (!std::isfinite(x) || (p.log_x && x <= 0)) continue;
      if (ser.style != PlotStyle::Band && (!std::isfinite(y) || (p.log_y && y <= 0))) continue;
      if (ranged && (!std::isfinite(lo) || !std::isfinite(hi))) continue;
      const double lo_c = p.log_y && ranged && lo <= 0 ? (y > 0 ? y * 1e-3 : 1e-300) : lo;
      s << num(x) << " " << num(y) << " " << num(lo_c) << " " << num(hi) << "\n";
    }
    s << "EOD\n";
    const std::string color =
        ser.color.empty() ? kPalette[i % (sizeof kPalette / sizeof kPalette[0])] : ser.color;
    std::string c = "$s" + std::to_string(i);
    const std::string lc = " lc rgb " + gpString(color) + (ser.dashed ? " dt 2" : "");
    switch (ser.style) {
      case PlotStyle::Lines: c += " using 1:2 with lines lw 2" + lc; break;
      case PlotStyle::Points: c += " using 1:2 with points pt 7 ps 0.6" + lc; break;
      case PlotStyle::LinesPoints: c += " using 1:2 with linespoints pt 7 ps 0.8 lw 2" + lc; break;
      case PlotStyle::Steps: c += " using 1:2 with steps lw 2" + lc; break;
      case PlotStyle::Boxes: c += " using 1:2 with boxes" + lc; break;
      case PlotStyle::ErrorBars: c += " using 1:2:3:4 with yerrorlines pt 7 ps 0.8 lw 2" + lc; break;
      case PlotStyle::Band:
        c += " using 1:3:4 with filledcurves fs transparent solid 0.2 noborder" + lc;
        break;
    }
    c += ser.title.empty() ? " notitle" : " title " + gpString(ser.title);
    clauses.push_back(c);
  }
  for (std::size_t i = 0; i < p.ref_lines.size(); ++i) {
    const PlotRefLine& r = p.ref_lines[i];
    if (p.log_y && r.y <= 0) continue;
    clauses.push_back(num(r.y) + " with lines lw 1.5 dt 3 lc rgb \"#404040\"" +
                      (r.title.empty() ? " notitle" : " title " + gpString(r.title)));
  }
  std::size_t points = 0;
  for (const PlotSeries& ser : p.series) points += ser.x.size();
  if (points == 0) {  // gnuplot refuses a plot without data: draw an empty frame that says so
    s << "unset logscale\nset xrange [0:1]\nset yrange [0:1]\n"
         "set label 1 \"no data\" at 0.5,0.5 center\n";
    clauses = {"-1 notitle"};
  }
  s << "plot ";
  for (std::size_t i = 0; i < clauses.size(); ++i) s << (i ? ", \\\n     " : "") << clauses[i];
  s << "\nunset output\n";
  return s.str();
}

void savePlot(const Plot& plot, const std::string& png_path, const std::string& program_in) {
  const std::string program = gnuplotProgram(program_in);
  const Probe pr = probe(program);
  if (!pr.problem.empty()) throw ProcessingError(pr.problem);
  std::string stem = png_path;
  if (stem.size() > 4 && stem.compare(stem.size() - 4, 4, ".png") == 0)
    stem.resize(stem.size() - 4);
  const std::string gp = stem + ".gp";
  {
    std::ofstream f(gp);
    if (!f) throw InputError("cannot write plot script '" + gp + "'");
    f << gnuplotScript(plot, png_path, pr.terminal);
    if (!f) throw InputError("cannot write plot script '" + gp + "'");
  }
  std::string out;
  const int rc = runCapture(shellQuote(*findProgram(program)) + " " + shellQuote(gp), out);
  if (rc != 0)
    throw ProcessingError("gnuplot failed on '" + gp + "' (exit " + std::to_string(rc) +
                          "): " + out.substr(0, 400));
}

}  // namespace st::app

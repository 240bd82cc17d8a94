/// @file plot.hpp
/// PNG plots through gnuplot (Debian `gnuplot-nox`), shared by the commands that report
/// (montecarlo, replay). A Plot is a title, labelled axes and several series (lines, points,
/// steps, histogram boxes, error bars or a shaded band); savePlot() writes one self-contained
/// gnuplot script next to the PNG (data inline, so `gnuplot file.gp` redraws it) and runs it.
///
/// The PNG terminal is pngcairo when the installed gnuplot has it, else the libgd `png`.
/// A missing or failing gnuplot is a ProcessingError with a message saying what to install;
/// it never crashes the caller, which can keep the tables it already wrote.
#pragma once
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace st::app {

enum class PlotStyle {
  Lines,
  Points,
  LinesPoints,
  Steps,      ///< histogram outline / staircase (gnuplot `steps`)
  Boxes,      ///< histogram bars centred on x
  ErrorBars,  ///< y with the interval [y_lo, y_hi] as error bars, joined by a line
  Band,       ///< shaded area between y_lo and y_hi (y is ignored)
};

struct PlotSeries {
  PlotSeries() = default;
  PlotSeries(std::string title_, PlotStyle style_) : title(std::move(title_)), style(style_) {}
  std::string title;  ///< legend entry (empty: no entry)
  PlotStyle style = PlotStyle::LinesPoints;
  std::vector<double> x, y;
  std::vector<double> y_lo, y_hi;  ///< for ErrorBars and Band: same length as x
  std::string color;               ///< gnuplot colour, e.g. "#1f77b4"; empty = automatic
  bool dashed = false;
};

/// A horizontal reference line (e.g. a threshold or the expected value).
struct PlotRefLine {
  double y;
  std::string title;
};

struct Plot {
  std::string title, xlabel, ylabel;
  std::vector<PlotSeries> series;
  std::vector<PlotRefLine> ref_lines;
  bool log_x = false, log_y = false;  ///< non-positive values are dropped on a log axis
  std::optional<double> x_min, x_max, y_min, y_max;
  int width_px = 800, height_px = 500;
  std::string key = "top right";  ///< gnuplot `set key` position, "off" hides the legend
};

/// A plot with its title and axis labels, the rest default.
Plot makePlot(std::string title, std::string xlabel, std::string ylabel);

/// The gnuplot program: `override` if not empty, else $ST_GNUPLOT, else "gnuplot" on PATH.
std::string gnuplotProgram(const std::string& override_path = "");

/// Empty when `program` can be run and has a PNG terminal; otherwise the reason, phrased
/// for a user (what is missing and what to install).
std::string gnuplotProblem(const std::string& program);

/// The gnuplot script for `plot` rendering to `png_path` with terminal `terminal`
/// ("pngcairo" or "png"). Exposed for tests.
std::string gnuplotScript(const Plot& plot, const std::string& png_path,
                          const std::string& terminal);

/// Writes `<png_path without .png>.gp` and runs gnuplot on it. Throws ProcessingError when
/// gnuplot is missing, has no PNG terminal, or fails (its own message is included), and
/// InputError when the script cannot be written.
void savePlot(const Plot& plot, const std::string& png_path, const std::string& program = "");

}  // namespace st::app

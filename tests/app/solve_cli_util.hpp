/// @file solve_cli_util.hpp
/// Running `startracker solve` from a test and reading its one JSON object.
#pragma once
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <string>

#include "common/attitude.hpp"
#include "common/conventions.hpp"
#include "tests/support/test_paths.hpp"

namespace st::test {

inline std::string tetra3Frame(const std::string& name = "2019-07-29T204726_Alt40_Azi-135_Try1") {
  return tetra3ImageDir() + "/" + name + ".tiff";
}

/// The focal length [px] `solve` fits on the eight tetra3 frames without a camera file.
constexpr double kTetra3ExactFx = 5117.7;

/// A camera file for the tetra3 frames as a datasheet gives it: OpenCV YAML, focal length
/// `rel_error` off kTetra3ExactFx, principal point at the centre, no distortion.
inline std::string writeTetra3Camera(const std::string& path, double rel_error) {
  const double f = kTetra3ExactFx * (1 + rel_error);
  std::ofstream(path) << "%YAML:1.0\n---\nimage_width: 1024\nimage_height: 768\n"
                      << "camera_matrix: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n"
                      << "   data: [ " << f << ", 0., 511.5, 0., " << f << ", 383.5, 0., 0., 1. ]\n"
                      << "distortion_coefficients: !!opencv-matrix\n   rows: 1\n   cols: 5\n"
                      << "   dt: d\n   data: [ 0., 0., 0., 0., 0. ]\n";
  return path;
}

/// gtest parameter names of relative focal errors: -0.02 -> "minus20permille".
inline std::string permilleName(double rel) {
  const int permille = static_cast<int>(std::lround(rel * 1000));
  return std::string(permille < 0 ? "minus" : "plus") + std::to_string(std::abs(permille)) +
         "permille";
}

/// Single-quoted for the shell (a ' inside becomes '\'').
inline std::string shellQuote(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

struct SolveRun {
  int rc = -1;
  std::string stdout_text;
  nlohmann::json json;  ///< null when stdout is not one JSON object
};

/// `startracker solve ARGS --json`, stderr dropped; parses stdout.
inline SolveRun solveJson(const std::string& args) {
  SolveRun r;
  r.rc = runCommand("(" + startrackerExe() + " solve --json " + args + " 2>/dev/null)",
                    &r.stdout_text);
  r.json = nlohmann::json::parse(r.stdout_text, nullptr, /*allow_exceptions=*/false);
  if (r.json.is_discarded()) r.json = nullptr;
  return r;
}

inline Quat quatOf(const nlohmann::json& j) {
  const auto& q = j.at("q_ib");
  return Quat(q[0].get<double>(), q[1].get<double>(), q[2].get<double>(), q[3].get<double>());
}

/// Angle [arcsec] between the attitudes of two solved JSON objects.
inline double attitudeDifferenceArcsec(const nlohmann::json& a, const nlohmann::json& b) {
  return rad2arcsec(quatOf(a).angularDistance(quatOf(b)));
}

}  // namespace st::test

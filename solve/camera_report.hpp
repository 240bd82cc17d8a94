/// @file camera_report.hpp
/// The camera part of solve's answer: the focal length and radial distortion the stars
/// support, with their 1-sigma (sensors/camera/camera_fit.hpp), the camera-model error term,
/// and, with a camera file, how the sky disagrees with it ("focal length appears 0.10 %
/// longer than camera.yaml"), in text and JSON.
#pragma once
#include <string>

#include <nlohmann/json.hpp>

#include "solve/solve_output.hpp"

namespace st::solve {

/// The discrepancy against --camera (empty without a camera file or when none is
/// significant), with the advice to calibrate.
std::string cameraDiscrepancy(const SolveReport& r);

/// {"fx", "fy", "cx", "cy", "k1", "k2", "source", "fit": {...}, "discrepancy"}.
nlohmann::ordered_json cameraJson(const SolveReport& r);

/// The "camera fit" line of the text answer (nothing when nothing was fitted); the
/// discrepancy goes to the log (solve_run.cpp), once.
void printCameraFitText(const SolveReport& r);

}  // namespace st::solve

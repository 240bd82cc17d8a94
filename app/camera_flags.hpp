/// @file camera_flags.hpp
/// `--camera FILE`, `--camera-section` and `--fov-deg` on a command (solve/camera_options.hpp
/// says what they mean).
#pragma once
#include <CLI/CLI.hpp>

#include "solve/camera_options.hpp"

namespace st::app {

void addCameraFlags(CLI::App& cmd, solve::CameraOptions& o);

}  // namespace st::app

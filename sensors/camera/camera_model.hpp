/// @file camera_model.hpp
/// A public seam type: its one definition is the installed header <startracker/camera_model.hpp>.
#pragma once
#include "startracker/camera_model.hpp"

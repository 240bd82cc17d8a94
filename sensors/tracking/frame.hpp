/// @file frame.hpp
/// A public seam type: its one definition is the installed header <startracker/frame.hpp>.
#pragma once
#include "startracker/frame.hpp"

/// @file errors.hpp
/// A public seam type: its one definition is the installed header <startracker/errors.hpp>.
#pragma once
#include "startracker/errors.hpp"

/// @file conventions.hpp
/// A public seam type: its one definition is the installed header <startracker/conventions.hpp>.
#pragma once
#include "startracker/conventions.hpp"

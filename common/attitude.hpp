/// @file attitude.hpp
/// A public seam type: its one definition is the installed header <startracker/attitude.hpp>.
#pragma once
#include "startracker/attitude.hpp"

/// @file plugin.cpp
/// The `startracker_mrpt` shared library for MRPT's stock tools: `rawlog-edit -p` and
/// `rawlog-grabber -p` only dlopen() a plugin, so registration must run from a static
/// initializer here (MRPT-NOTES.md).
#include "sensors/mrpt/rawlog_io.hpp"

namespace {
struct RegisterOnLoad {
  RegisterOnLoad() { st::registerStarTrackerClasses(); }
};
const RegisterOnLoad register_on_load;
}  // namespace

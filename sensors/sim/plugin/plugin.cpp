/// @file plugin.cpp
/// The `startracker_sim` shared library for MRPT's stock tools: the simulated star camera
/// and gyro (CSimulatedStarCamera, CSimulatedGyro) for `rawlog-grabber -p`, beside the
/// production plugin `startracker_mrpt`. Registration runs from a static initializer
/// (MRPT-NOTES.md: the tools only dlopen() a plugin).
#include "sensors/sim/simulated_sensors.hpp"

namespace {
struct RegisterOnLoad {
  RegisterOnLoad() { st::registerSimulatedSensors(); }
};
const RegisterOnLoad register_on_load;
}  // namespace

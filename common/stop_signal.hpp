/// @file stop_signal.hpp
/// SIGINT / SIGTERM as a request to stop, for the long commands (live, replay): they poll
/// stopSignal() between steps, then flush what they did, print its summary, say they were
/// interrupted and exit with kExitInterrupted. A second signal is not caught: it kills.
#pragma once

namespace st {

/// Exit code of a command stopped by SIGINT/SIGTERM (the shell's 128 + SIGINT).
constexpr int kExitInterrupted = 130;

/// Installs the handlers (once per command run; clears an earlier request).
void installStopSignals();
/// 0, or the signal that asked to stop.
int stopSignal();
/// "SIGINT" / "SIGTERM" (or "" when none).
const char* stopSignalName();

}  // namespace st

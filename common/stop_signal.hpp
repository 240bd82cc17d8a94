/// @file stop_signal.hpp
/// SIGINT / SIGTERM as a request to stop, for the long commands (live, replay): they poll
/// stopSignal() between steps, then flush what they did, print its summary, say they were
/// interrupted and exit with kExitInterrupted. A second signal more than 2 s after the first
/// kills; one sooner is the same request (timeout(1) sends its signal twice: to the process and
/// to its group, and a run under load was then killed before its summary).
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

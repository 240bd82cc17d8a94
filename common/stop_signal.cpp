#include "common/stop_signal.hpp"

#include <csignal>

namespace st {

namespace {
volatile std::sig_atomic_t g_signal = 0;
extern "C" void onStopSignal(int sig) {
  g_signal = sig;
  // The next one is not caught: a run stuck in a long step can still be stopped.
  std::signal(sig, SIG_DFL);
}
}  // namespace

void installStopSignals() {
  g_signal = 0;
  struct sigaction sa {};
  sa.sa_handler = onStopSignal;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}

int stopSignal() { return g_signal; }

const char* stopSignalName() {
  return g_signal == SIGINT ? "SIGINT" : g_signal == SIGTERM ? "SIGTERM" : "";
}

}  // namespace st

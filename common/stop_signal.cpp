#include "common/stop_signal.hpp"

#include <csignal>
#include <ctime>

namespace st {

namespace {
volatile std::sig_atomic_t g_signal = 0;
volatile std::sig_atomic_t g_first_s = 0;  // CLOCK_MONOTONIC seconds of the first signal

/// A repeat within this many seconds is the same request: timeout(1) sends its signal to the
/// process and again to its process group, and a second Ctrl-C that quickly is a bounce.
constexpr long kRepeatIsSameRequestS = 2;

long monotonicSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);  // async-signal-safe
  return static_cast<long>(ts.tv_sec);
}

extern "C" void onStopSignal(int sig) {
  if (g_signal == 0) {
    g_signal = sig;
    g_first_s = static_cast<std::sig_atomic_t>(monotonicSeconds());
    return;
  }
  if (monotonicSeconds() - g_first_s <= kRepeatIsSameRequestS) return;
  // A later one is not caught: a run stuck in a long step can still be stopped.
  std::signal(sig, SIG_DFL);
  std::raise(sig);
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

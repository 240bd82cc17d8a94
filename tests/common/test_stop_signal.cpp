// SIGINT / SIGTERM as a stop request (common/stop_signal.hpp): the first is a request, a
// repeat within 2 s the same request (timeout(1) sends its signal to the process and again to
// its process group: under load a live run was killed by the copy before its summary), a
// later one kills. Each case in a child process, so the test runner keeps its own handlers.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <thread>

#include "common/stop_signal.hpp"

namespace st {
namespace {

/// Runs `body` in a child; returns its wait status.
template <class Body>
int inChild(Body body) {
  const pid_t pid = fork();
  if (pid == 0) {
    body();
    _exit(0);
  }
  int status = 0;
  waitpid(pid, &status, 0);
  return status;
}

TEST(StopSignal, ARepeatWithinTwoSecondsIsTheSameRequest) {
  const int status = inChild([] {
    installStopSignals();
    std::raise(SIGINT);
    std::raise(SIGINT);  // timeout(1)'s second copy
    std::raise(SIGTERM);
    _exit(stopSignal() == SIGINT ? 7 : 8);
  });
  ASSERT_TRUE(WIFEXITED(status)) << "killed by signal " << WTERMSIG(status);
  EXPECT_EQ(WEXITSTATUS(status), 7);
}

TEST(StopSignal, ALaterOneKills) {
  const int status = inChild([] {
    installStopSignals();
    std::raise(SIGINT);
    std::this_thread::sleep_for(std::chrono::milliseconds(3100));
    std::raise(SIGINT);  // a run stuck in a long step can still be stopped
    _exit(9);
  });
  ASSERT_TRUE(WIFSIGNALED(status));
  EXPECT_EQ(WTERMSIG(status), SIGINT);
}

}  // namespace
}  // namespace st

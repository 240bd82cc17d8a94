// common/log.hpp: the process-wide verbosity policy (issue 21 item 10). -q keeps warnings
// and errors and drops info lines and progress bars; -v adds debug lines; every line carries
// the command's tag.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>

#include "common/log.hpp"
#include "common/progress.hpp"

namespace st {
namespace {

std::string captured(const std::function<void()>& speak) {
  testing::internal::CaptureStderr();
  speak();
  return testing::internal::GetCapturedStderr();
}

struct LogLevelGuard {
  ~LogLevelGuard() {
    log::setVerbosity(log::Verbosity::kNormal);
    log::setTag("");
  }
};

void speakAll() {
  log::info("info %d", 1);
  log::warn("warn %s", "two");
  log::debug("debug %.1f", 3.0);
  log::error("error");
}

TEST(Log, LevelsAndTag) {
  const LogLevelGuard guard;
  log::setTag("solve");
  log::setVerbosity(log::Verbosity::kNormal);
  EXPECT_EQ(captured(speakAll), "[solve] info 1\n[solve] warning: warn two\n[solve] error: error\n");
  log::setVerbosity(log::Verbosity::kQuiet);
  EXPECT_EQ(captured(speakAll), "[solve] warning: warn two\n[solve] error: error\n");
  log::setVerbosity(log::Verbosity::kVerbose);
  EXPECT_EQ(captured(speakAll),
            "[solve] info 1\n[solve] warning: warn two\n[solve] debug: debug 3.0\n"
            "[solve] error: error\n");
  log::setTag("");
  EXPECT_EQ(captured([] { log::info("no tag\n"); }), "no tag\n");  // one newline, not two
}

/// What `speak` writes to stderr while stderr is a terminal (a pseudo-terminal's far end).
std::string onTerminal(const std::function<void()>& speak) {
  const int master = posix_openpt(O_RDWR | O_NOCTTY);
  if (master < 0 || grantpt(master) != 0 || unlockpt(master) != 0) return "<no pty>";
  const int slave = open(ptsname(master), O_RDWR | O_NOCTTY);
  if (slave < 0) {
    close(master);
    return "<no pty>";
  }
  std::fflush(stderr);
  const int saved = dup(STDERR_FILENO);
  dup2(slave, STDERR_FILENO);
  speak();
  std::fflush(stderr);
  dup2(saved, STDERR_FILENO);
  close(saved);
  close(slave);
  std::string out;
  char buf[4096];
  fcntl(master, F_SETFL, O_NONBLOCK);
  for (ssize_t n; (n = read(master, buf, sizeof buf)) > 0;) out.append(buf, std::size_t(n));
  close(master);
  return out;
}

void runBar() {
  ProgressBar bar("work", 10);
  for (int i = 1; i <= 10; ++i) bar.update(static_cast<std::size_t>(i));
}

TEST(Log, ProgressBarOnlyOnATerminalAndSilentWhenQuiet) {
  const LogLevelGuard guard;
  log::setVerbosity(log::Verbosity::kNormal);
  // A redirected stderr (a file, a pipe: here gtest's capture file) gets no bar (issue 39).
  EXPECT_EQ(captured(runBar), "");
  const std::string on_tty = onTerminal(runBar);
  if (on_tty == "<no pty>") GTEST_SKIP() << "no pseudo-terminal on this machine";
  EXPECT_NE(on_tty.find("work ["), std::string::npos);
  log::setVerbosity(log::Verbosity::kQuiet);
  EXPECT_EQ(onTerminal(runBar), "");
}

}  // namespace
}  // namespace st

// common/log.hpp: the process-wide verbosity policy (issue 21 item 10). -q keeps warnings
// and errors and drops info lines and progress bars; -v adds debug lines; every line carries
// the command's tag.
#include <gtest/gtest.h>

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

TEST(Log, ProgressBarSilentWhenQuiet) {
  const LogLevelGuard guard;
  log::setVerbosity(log::Verbosity::kQuiet);
  EXPECT_EQ(captured([] {
              ProgressBar bar("work", 10);
              for (int i = 1; i <= 10; ++i) bar.update(static_cast<std::size_t>(i));
            }),
            "");
  log::setVerbosity(log::Verbosity::kNormal);
  EXPECT_NE(captured([] {
              ProgressBar bar("work", 10);
              for (int i = 1; i <= 10; ++i) bar.update(static_cast<std::size_t>(i));
            }).find("work ["),
            std::string::npos);
}

}  // namespace
}  // namespace st

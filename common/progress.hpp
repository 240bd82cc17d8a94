/// @file progress.hpp
/// A text progress bar for long jobs, on stderr, redrawn on one line, and only when stderr
/// is a terminal (a file or pipe gets the messages alone). Silent under -q
/// (st::log::quiet(), read when the bar is made) whatever `enabled` says.
#pragma once
#include <chrono>
#include <cstddef>
#include <string>

namespace st {

class ProgressBar {
 public:
  ProgressBar(std::string label, std::size_t total, bool enabled = true);
  ~ProgressBar();
  /// Sets the number of finished items (thread-compatible, call from one thread).
  void update(std::size_t done);
  void increment() { update(done_ + 1); }
  void finish();

 private:
  void draw();
  std::string label_;
  std::size_t total_;
  std::size_t done_ = 0;
  bool tty_;  // before enabled_, which reads it
  bool enabled_;
  bool finished_ = false;
  std::chrono::steady_clock::time_point start_, last_draw_;
};

}  // namespace st

/// @file progress.hpp
/// A text progress bar for long jobs, on stderr. On a terminal it redraws one line; when
/// stderr is a file or pipe (CI logs) it prints a line every 10 %. Silent under -q
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
  void draw(bool final_line);
  std::string label_;
  std::size_t total_;
  std::size_t done_ = 0;
  bool enabled_;
  bool tty_;
  bool finished_ = false;
  int last_decile_ = -1;
  std::chrono::steady_clock::time_point start_, last_draw_;
};

}  // namespace st

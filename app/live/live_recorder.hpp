/// @file live_recorder.hpp
/// What `startracker live` does with every observation its sensors deliver: writes it to the
/// rawlog (images as external PNGs), counts it per label and, for star-tracker fixes, per
/// outcome; and hands it to the navigator (when the filter runs).
/// The rawlog is written in timestamp order, as replay reads it: sensors deliver late (a frame
/// is stamped at mid-exposure and its fix after processing, while the gyro keeps sampling),
/// so observations are held `hold_s` past the newest timestamp seen and written sorted;
/// finish() writes the rest. One that still arrives after later ones were written is written
/// anyway (never lost) and counted.
/// SIGKILL or a crash loses only what is held or not yet flushed: the rawlog is flushed every
/// `flush_s` of wall time, so at most hold_s + flush_s (0.5 + 0.25 s) of observations before
/// the kill are missing (tests/app/test_live_kill.cpp). hold_s is the navigator's default
/// reorder window: a fix later than that is of no use to the filter either.
#pragma once
#include <mrpt/obs/CObservation.h>

#include <chrono>
#include <cstdio>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "app/live/live_navigator.hpp"
#include "sensors/mrpt/rawlog_io.hpp"

namespace st::app {

class LiveRecorder {
 public:
  /// `nav` may be null (no filter); both must outlive the recorder.
  LiveRecorder(RawlogWriter& writer, LiveNavigator* nav, double hold_s = 0.5,
               double flush_s = 0.25)
      : writer_(writer), nav_(nav), hold_s_(hold_s), flush_s_(flush_s) {}

  /// Takes a batch: to the navigator at once, to the rawlog once hold_s old.
  void record(std::vector<mrpt::obs::CObservation::Ptr> batch);
  /// Writes everything still held and flushes.
  void finish();
  /// Observations written after a later one (arrived more than hold_s late).
  int writtenOutOfOrder() const { return out_of_order_; }
  void setNavigator(LiveNavigator* nav) { nav_ = nav; }

  std::size_t written() const { return written_; }
  /// Writes a recording marker (rawlog_io.hpp) at once; counted in the rawlog's lines, not
  /// among the sensors' observations.
  void writeMarker(const mrpt::obs::CObservation& marker);
  /// The newest timestamp written so far (INVALID_TIMESTAMP before the first).
  mrpt::Clock::time_point lastWritten() const { return last_written_.value_or(mrpt::Clock::time_point{}); }
  /// "rawlog: ..., N observations" and one line per label (tests parse these lines).
  void printRawlogSummary(const std::string& path, std::FILE* out) const;
  /// Frames, solved, tracking, lost-in-space, and the failures counted by their cause.
  void printTrackerSummary(std::FILE* out) const;

 private:
  void write(const mrpt::obs::CObservation::Ptr& o);
  void writeOlderThan(mrpt::Clock::time_point limit);
  void flushIfDue();

  RawlogWriter& writer_;
  LiveNavigator* nav_;
  double hold_s_, flush_s_;
  std::chrono::steady_clock::time_point last_flush_ = std::chrono::steady_clock::now();
  int flushes_ = 0;
  double flush_time_s_ = 0, flush_max_s_ = 0;  // the cost of flushing, in the summary
  std::multimap<mrpt::Clock::time_point, mrpt::obs::CObservation::Ptr> held_;
  std::optional<mrpt::Clock::time_point> newest_, last_written_;
  int out_of_order_ = 0;
  std::map<std::string, std::size_t> per_label_;
  std::map<FrameFailure, int> failures_;
  int frames_ = 0, solved_ = 0, tracking_ = 0, lis_ = 0, reacquired_ = 0, image_no_ = 0;
  std::size_t written_ = 0, markers_ = 0;
  std::map<std::string, int> head_frames_;  ///< STAR_TRACKER observations per label (head)
  std::set<int64_t> frame_times_;           ///< their distinct timestamps
};

}  // namespace st::app

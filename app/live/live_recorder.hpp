/// @file live_recorder.hpp
/// What `startracker live` does with every observation its sensors deliver: writes it to the
/// rawlog (images as external PNGs), counts it per label and, for star-tracker fixes, per
/// outcome; and hands it to the navigator (when the filter runs).
#pragma once
#include <mrpt/obs/CObservation.h>

#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "app/live/live_navigator.hpp"
#include "sensors/mrpt/rawlog_io.hpp"

namespace st::app {

class LiveRecorder {
 public:
  /// `nav` may be null (no filter); both must outlive the recorder.
  LiveRecorder(RawlogWriter& writer, LiveNavigator* nav) : writer_(writer), nav_(nav) {}

  /// Writes a batch in timestamp order.
  void record(std::vector<mrpt::obs::CObservation::Ptr> batch);
  void setNavigator(LiveNavigator* nav) { nav_ = nav; }

  std::size_t written() const { return written_; }
  /// "rawlog: ..., N observations" and one line per label (tests parse these lines).
  void printRawlogSummary(const std::string& path, std::FILE* out) const;
  /// Frames, solved, tracking, lost-in-space, and the failures counted by their cause.
  void printTrackerSummary(std::FILE* out) const;

 private:
  RawlogWriter& writer_;
  LiveNavigator* nav_;
  std::map<std::string, std::size_t> per_label_;
  std::map<FrameFailure, int> failures_;
  int frames_ = 0, solved_ = 0, tracking_ = 0, lis_ = 0, image_no_ = 0;
  std::size_t written_ = 0;
};

}  // namespace st::app

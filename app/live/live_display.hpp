/// @file live_display.hpp
/// `startracker live --gui`: an OpenCV window with the last frame (contrast-stretched),
/// the detected blobs (small circles), the identified stars (circles labelled with their
/// catalog numbers) and the current attitude (RA/Dec/roll of the filter, else of the fix).
/// Runs in the main thread (GUI toolkits want that). Without a display it reports why and
/// the run goes on headless.
#pragma once
#include <opencv2/core.hpp>
#include <optional>
#include <string>

#include "common/attitude.hpp"
#include "sensors/mrpt/observation_star_tracker.hpp"

namespace st::app {

class LiveDisplay {
 public:
  /// False (reason in *why) when no window can be opened (no DISPLAY / WAYLAND_DISPLAY).
  bool open(const std::string& title, std::string* why);
  bool isOpen() const { return open_; }
  /// Draws and shows; `attitude` is the filter's estimate when it has one.
  void show(const cv::Mat& frame, const CObservationStarTracker* fix,
            const std::optional<Quat>& attitude);
  /// Polls the window's events; true when the user pressed q or Esc.
  bool quitRequested();
  void close();

  /// The annotated picture (also used without a window, e.g. for a snapshot).
  static cv::Mat render(const cv::Mat& frame, const CObservationStarTracker* fix,
                        const std::optional<Quat>& attitude);

 private:
  bool open_ = false;
  std::string title_;
};

}  // namespace st::app

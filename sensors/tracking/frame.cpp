#include "sensors/tracking/frame.hpp"

namespace st {

const char* toString(StarTrackerMode mode) {
  switch (mode) {
    case StarTrackerMode::kLostInSpace:
      return "lost-in-space";
    case StarTrackerMode::kTracking:
      return "tracking";
    case StarTrackerMode::kFailed:
      return "failed";
  }
  return "unknown";
}

const char* toString(FrameFailure f) {
  switch (f) {
    case FrameFailure::kNone:
      return "none";
    case FrameFailure::kDetection:
      return "detection";
    case FrameFailure::kTooFewStars:
      return "too-few-stars";
    case FrameFailure::kNoMatch:
      return "no-match";
    case FrameFailure::kRejected:
      return "rejected";
    case FrameFailure::kTooFewPredicted:
      return "too-few-predicted";
    case FrameFailure::kTooFewInGate:
      return "too-few-in-gate";
    case FrameFailure::kSolver:
      return "solver";
    case FrameFailure::kResiduals:
      return "residuals";
    case FrameFailure::kInconsistentPrediction:
      return "inconsistent-prediction";
    case FrameFailure::kUnknown:
      return "unknown";
    case FrameFailure::kNoImage:
      return "no-image";
    case FrameFailure::kFrozenImage:
      return "frozen-image";
    case FrameFailure::kClockRefused:
      return "clock-refused";
  }
  return "unknown";
}

const char* toString(PredictionSource s) {
  switch (s) {
    case PredictionSource::kNone:
      return "none";
    case PredictionSource::kExternal:
      return "external";
    case PredictionSource::kGyro:
      return "gyro";
    case PredictionSource::kRateMatch:
      return "rate match";
  }
  return "unknown";
}

}  // namespace st

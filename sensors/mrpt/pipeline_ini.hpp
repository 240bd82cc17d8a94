/// @file pipeline_ini.hpp
/// The .ini keys of a star tracker (TrackerOptions with its DetectorOptions, IdentifyOptions
/// and VerifyOptions, plus the observation label), one SectionSchema read the same way by
/// CStarTrackerSensor (in its own section) and by the navigator (tracker.ini's [pipeline]):
/// one list of keys, one meaning for each, printable by `startracker config`.
///
/// Key names: the prefix is the stage the key tunes, so that the stages' same-named options
/// never collide (a gate of tracking is not the gate of verification):
///   detect_   detection and centroiding (DetectorOptions)
///   lis_      lost-in-space identification (IdentifyOptions, lis_algorithm, its sigma floor)
///   verify_   verification of a hypothesis, LIS and recursive (VerifyOptions)
///   track_    tracking: windows, gates, loss tests (TrackerOptions)
///   f2f_      frame-to-frame prediction when nothing is given (TrackerOptions)
///   cam_      the camera model: lost-in-space healing of the file, online refinement and
///             the camera-model error term (TrackerOptions, OnlineCameraOptions)
/// Unprefixed: the camera's noise model and PSF shared by every stage (gain_e_per_adu,
/// read_noise_adu, psf_sigma_px, centroider), exposure_s and sensor_label.
/// The old names (gate_sigma, solver, max_stars, ...) are refused naming their new name.
/// Not keys: R_body_cam (the sensor's MRPT pose gives it), DetectorOptions::dark_frame (an
/// image; detect_dark_file names a file of one), VerifyOptions::scale_tolerance (copied from lis_scale_tolerance) and
/// VerifyOptions::enabled (off only in tests: a tracker that accepts every hypothesis).
#pragma once
#include <string>

#include "config/ini_reader.hpp"
#include "config/schema.hpp"
#include "sensors/mrpt/observation_from_frame.hpp"
#include "sensors/tracking/tracker_options.hpp"

namespace st {

/// Every tracker key (TrackerOptions).
const SectionSchema<TrackerOptions>& trackerIniSchema();
/// trackerIniSchema() plus `sensor_label`.
const SectionSchema<PipelineOptions>& pipelineIniSchema();

/// Reads the tracker keys of `section` that are present over `o` (absent keys keep o's
/// values), strictly, then checks the result once (TrackerOptions::isValid), reporting a bad
/// value under its key. Throws InputError naming the file, section and key.
void readTrackerOptions(const IniReader& r, const std::string& section, TrackerOptions& o);

/// The check of readTrackerOptions alone (TrackerOptions::isValid, the error under its key).
void checkTrackerOptions(const IniReader& r, const std::string& section, const TrackerOptions& o);

/// The same for PipelineOptions (the tracker keys and `sensor_label`).
void readPipelineOptions(const IniReader& r, const std::string& section, PipelineOptions& o);

/// The ini key of the option that TrackerOptions::isValid's message `why` blames ("" when
/// none): validation names fields, the user wrote keys.
std::string trackerKeyOfError(const std::string& why);

}  // namespace st

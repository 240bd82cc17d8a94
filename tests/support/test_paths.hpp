/// @file test_paths.hpp
/// Where tests find data: the repository, the shared real data, the startracker binary.
#pragma once
#include <string>
#include <vector>

namespace st::test {

/// Repository root (absolute).
std::string repoDir();
/// ../shared/data (the workplace's real data; only for data too large to commit, e.g. a full
/// Hipparcos file); override with env ST_SHARED_DATA_DIR. Tests must skip when it is absent.
std::string sharedDataDir();
/// The committed Hipparcos subset in catalog/data/.
std::string hipparcosSubsetPath();
/// The eight real tetra3 frames (committed in tests/data/tetra3).
std::string tetra3ImageDir();
/// The eight real tetra3 frames (.tiff), sorted by name.
std::vector<std::string> tetra3Frames();
/// The thirty real Swarm star-camera frames (committed in tests/data/swarm): .png, each with
/// its astrometry.net .wcs beside it.
std::string swarmImageDir();
/// Their .png files, sorted by name.
std::vector<std::string> swarmFrames();
/// The Yale Bright Star Catalogue binary (committed in catalog/data).
std::string bsc5Path();
/// A fresh empty temporary directory for one test (removed by the OS, not by the test).
std::string makeTempDir(const std::string& tag);
/// Path of the built `startracker` executable (for end-to-end tests).
std::string startrackerExe();

/// Runs a shell command, returns its exit code; stdout+stderr go to `output`.
int runCommand(const std::string& cmd, std::string* output = nullptr);

/// The whole file (bytes as they are; "" when it cannot be read).
std::string fileBytes(const std::string& path);

}  // namespace st::test

/// @file rawlog_io.hpp
/// Observation-only rawlogs (gz), written and read one object at a time, with the traps of
/// MRPT-NOTES.md handled: classes registered first, and a class MRPT does not know is an
/// error naming the file and object index instead of the silent truncation of
/// mrpt::obs::CRawlog::loadFromRawLogFile.
///
/// External images: a rawlog `dir/run.rawlog` keeps its external images in `dir/run_Images/`
/// (MRPT's own convention, found by RawLogViewer and rawlog-edit).
#pragma once
#include <mrpt/img/CImage.h>
#include <mrpt/obs/CObservation.h>

#include <cstddef>
#include <deque>
#include <memory>
#include <string>
#include <vector>

namespace mrpt::io {
class CFileGZInputStream;
class CFileGZOutputStream;
}  // namespace mrpt::io
namespace mrpt::serialization {
class CArchive;
}

namespace st {

/// Registers our observation classes with mrpt::rtti and our sensors with the
/// mrpt::hwdrivers::CGenericSensor factory. Idempotent and thread-safe; the plugin
/// (sensors/mrpt/plugin/) calls it from a static initializer.
void registerStarTrackerClasses();

/// `dir/stem_Images` for a rawlog `dir/stem.rawlog` (extension removed).
std::string rawlogImagesDir(const std::string& rawlog_path);

/// Writes observations to a gz rawlog, counting them.
class RawlogWriter {
 public:
  /// Throws InputError naming the file when it cannot be created.
  explicit RawlogWriter(const std::string& path, int gz_level = 1);
  ~RawlogWriter();
  RawlogWriter(const RawlogWriter&) = delete;
  RawlogWriter& operator=(const RawlogWriter&) = delete;

  void write(const mrpt::obs::CObservation& obs);
  /// Number of objects written so far.
  std::size_t count() const { return count_; }
  const std::string& path() const { return path_; }

  /// `<stem>_Images` beside the rawlog (created on the first externalizeImage).
  const std::string& imagesDir() const { return images_dir_; }
  /// Saves `img` as `imagesDir()/file_name` (PNG keeps 16 bits) and turns `img` into an
  /// external reference to it, so the next write() stores only the name. Throws InputError
  /// when the directory or file cannot be written.
  void externalizeImage(mrpt::img::CImage& img, const std::string& file_name);

  /// Flushes and closes; further writes throw. Also done by the destructor.
  void close();

 private:
  std::string path_, images_dir_;
  std::unique_ptr<mrpt::io::CFileGZOutputStream> file_;
  std::unique_ptr<mrpt::serialization::CArchive> ar_;
  std::size_t count_ = 0;
  bool images_dir_made_ = false;
};

/// Streams the observations of an observation-only rawlog (plain or gz), counting objects.
/// Registers our classes itself. `<stem>_Images` becomes MRPT's images path base (a
/// process-wide setting) so external images load, and so a missing folder is found missing
/// rather than its files looked up in the folder of an earlier rawlog.
class RawlogReader {
 public:
  /// Throws InputError naming the file when it is missing or cannot be opened.
  explicit RawlogReader(const std::string& path);
  ~RawlogReader();
  RawlogReader(const RawlogReader&) = delete;
  RawlogReader& operator=(const RawlogReader&) = delete;

  /// The next observation, or nullptr at the end of the file. Throws InputError naming the
  /// file and the object index (0-based) for a truncated or corrupt file, a class MRPT does
  /// not know (e.g. ours without registration or the plugin), or an object that is not an
  /// observation (actions / sensory frames: not an observation-only rawlog).
  mrpt::obs::CObservation::Ptr next();

  /// Objects read so far.
  std::size_t count() const { return count_; }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  std::unique_ptr<mrpt::io::CFileGZInputStream> file_;
  std::unique_ptr<mrpt::serialization::CArchive> ar_;
  std::size_t count_ = 0;
  bool at_end_ = false;
};

/// Reads the whole rawlog (see RawlogReader for the errors).
std::vector<mrpt::obs::CObservation::Ptr> readRawlog(const std::string& path);

/// The external images (CObservationImage) of observations labelled `sensor_label`, looked up
/// where MRPT will load them (CImage::getImagesPathBase(), which RawlogReader sets to the
/// rawlog's `<stem>_Images`).
struct ExternalImages {
  std::size_t external = 0;   ///< images stored outside the rawlog
  std::size_t missing = 0;    ///< of those, files not found
  std::string first_missing;  ///< path of the first missing file
};
ExternalImages checkExternalImages(const std::vector<mrpt::obs::CObservation::Ptr>& obs,
                                   const std::string& sensor_label);

}  // namespace st

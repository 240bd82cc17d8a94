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
#include <cstdint>
#include <deque>
#include <memory>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "common/errors.hpp"

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

/// A live recording begins and ends with an MRPT comment observation (CObservationComment,
/// shown by RawLogViewer and rawlog-edit) whose text begins with one of these words (MRPT
/// does not store a comment's label): a recording that has the first but not the second was
/// cut (the recorder was killed or lost power), which replay says.
constexpr const char* kRecordingStartLabel = "RECORDING_START";
constexpr const char* kRecordingEndLabel = "RECORDING_END";
/// The marker `label` ("<label>: <text>"), stamped `when`: the start marker carries no time
/// (INVALID_TIMESTAMP), the end marker the last observation's, so that neither is out of
/// order among the sensors' timestamps nor paced by replay --realtime.
mrpt::obs::CObservation::Ptr recordingMarker(const std::string& label, const std::string& text,
                                             mrpt::Clock::time_point when = {});
/// Whether `obs` is the marker `label`.
bool isRecordingMarker(const mrpt::obs::CObservation& obs, const std::string& label);

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

  /// Makes everything written so far readable from the file even if the process is killed
  /// next: the gz stream has no flush, so this ends its gzip member and appends a new one
  /// (a file of several members is one valid gz stream, read by zlib and MRPT as one).
  void flush();
  /// Flushes and closes; further writes throw. Also done by the destructor.
  void close();

 private:
  std::string path_, images_dir_;
  std::unique_ptr<mrpt::io::CFileGZOutputStream> file_;
  std::unique_ptr<mrpt::serialization::CArchive> ar_;
  std::size_t count_ = 0;
  int gz_level_ = 1;
  bool images_dir_made_ = false;
};

/// A rawlog that stops being readable part way: truncated (a recording cut by a crash or
/// power loss, a copy cut short, a gz file cut anywhere) or bytes that are no MRPT object.
/// Thrown by RawlogReader::next() (an InputError, so callers that want the whole file treat
/// it as bad input); readRawlogUpToDamage() keeps what came before it instead.
class RawlogDamageError : public InputError {
 public:
  RawlogDamageError(const std::string& what, std::size_t object, std::uint64_t offset,
                    std::string reason)
      : InputError(what), object(object), offset(offset), reason(std::move(reason)) {}
  std::size_t object;    ///< 0-based index of the object that could not be read
  std::uint64_t offset;  ///< its byte offset in the (uncompressed) object stream
  std::string reason;    ///< MRPT's error, first line
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

  /// The next observation, or nullptr at the end of the file. Throws RawlogDamageError (an
  /// InputError) naming the file, the object index (0-based) and its byte offset for a
  /// truncated or corrupt file; InputError for a class MRPT does
  /// not know (e.g. ours without registration or the plugin), or an object that is not an
  /// observation (actions / sensory frames: not an observation-only rawlog).
  mrpt::obs::CObservation::Ptr next();

  /// Objects read so far.
  std::size_t count() const { return count_; }
  /// Bytes of the (uncompressed) object stream consumed by the objects read so far.
  std::uint64_t offset() const { return offset_; }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  std::unique_ptr<mrpt::io::CFileGZInputStream> file_;
  std::unique_ptr<mrpt::serialization::CArchive> ar_;
  std::size_t count_ = 0;
  std::uint64_t offset_ = 0;
  bool at_end_ = false;
  std::size_t budget_ = 0;  ///< allocations one object may make (mrpt_allocation.hpp)
};

/// Reads the whole rawlog (see RawlogReader for the errors).
std::vector<mrpt::obs::CObservation::Ptr> readRawlog(const std::string& path);

/// Where and why readRawlogUpToDamage() stopped before the end of the file.
struct RawlogDamage {
  bool damaged = false;     ///< false: the file was read to its end
  std::size_t object = 0;   ///< index of the first unreadable object (= observations kept)
  std::uint64_t offset = 0; ///< its byte offset in the uncompressed object stream
  std::string reason;       ///< MRPT's error, first line
  std::string message;      ///< one line naming the file, object, offset and reason
};

/// Reads a rawlog up to the first damage (truncation, corrupt bytes): the intact
/// observations before it are returned and `damage` says where and why reading stopped,
/// as MRPT's own tools do. A file whose first object is unreadable (not a rawlog, or cut
/// before any object ends), an unknown class or a non-observation object still throw
/// InputError, as readRawlog().
std::vector<mrpt::obs::CObservation::Ptr> readRawlogUpToDamage(const std::string& path,
                                                               RawlogDamage* damage);
/// The same reading, streamed: `visit` sees each intact observation in turn and none is
/// kept (an hour of 10 Hz frames and 100 Hz gyro is 468,000 observations, 1.7 GB held).
/// Returns the number visited; `damage` as above; the same errors.
std::size_t visitRawlogUpToDamage(const std::string& path,
                                  const std::function<void(const mrpt::obs::CObservation::Ptr&)>& visit,
                                  RawlogDamage* damage);

/// The external images (CObservationImage) of observations labelled `sensor_label`, looked up
/// where MRPT will load them (CImage::getImagesPathBase(), which RawlogReader sets to the
/// rawlog's `<stem>_Images`).
struct ExternalImages {
  std::size_t external = 0;   ///< images stored outside the rawlog
  std::size_t missing = 0;    ///< of those, files not found
  std::string first_missing;  ///< path of the first missing file
  /// Counts `o` when it is a CObservationImage labelled `sensor_label`.
  void add(const mrpt::obs::CObservation& o, const std::string& sensor_label);
};

}  // namespace st

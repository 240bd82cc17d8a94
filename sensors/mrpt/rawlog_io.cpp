#include "sensors/mrpt/rawlog_io.hpp"

#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CObservationComment.h>
#include <mrpt/obs/CObservationImage.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/rtti/CObject.h>
#include <mrpt/serialization/CArchive.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <mutex>

#include "common/errors.hpp"
#include "sensors/mrpt/jpeg_errors.hpp"
#include "sensors/mrpt/mrpt_allocation.hpp"
#include "sensors/mrpt/observation_star_tracker.hpp"
#include "sensors/mrpt/star_tracker_sensor.hpp"

namespace st {

namespace fs = std::filesystem;

void registerStarTrackerClasses() {
  static std::once_flag once;
  std::call_once(once, [] {
    // Manual registration (MRPT-NOTES.md): without it MRPT cannot create the class by name
    // when reading, and CRawlog stops silently at the first such object.
    mrpt::rtti::registerClass(CLASS_ID(CObservationStarTracker));
    registerStarTrackerSensor();
  });
}

std::string rawlogImagesDir(const std::string& rawlog_path) {
  const fs::path p(rawlog_path);
  return (p.parent_path() / (p.stem().string() + "_Images")).string();
}

// ---------------------------------------------------------------------------------------
RawlogWriter::RawlogWriter(const std::string& path, int gz_level)
    : path_(path), images_dir_(rawlogImagesDir(path)), gz_level_(gz_level) {
  file_ = std::make_unique<mrpt::io::CFileGZOutputStream>();
  std::string err;
  if (!file_->open(path, gz_level, err)) {
    throw InputError("rawlog '" + path + "': cannot create the file" +
                     (err.empty() ? "" : " (" + err + ")"));
  }
  ar_ = mrpt::serialization::archiveUniquePtrFrom(*file_);
}

RawlogWriter::~RawlogWriter() {
  try {
    close();
  } catch (...) {  // a destructor must not throw; close() explicitly to see errors
  }
}

void RawlogWriter::write(const mrpt::obs::CObservation& obs) {
  if (!ar_) throw ProcessingError("rawlog '" + path_ + "': write after close");
  try {
    ar_->WriteObject(&obs);
  } catch (const std::exception& e) {
    throw ProcessingError("rawlog '" + path_ + "': cannot write object " +
                          std::to_string(count_) + ": " + e.what());
  }
  ++count_;
}

void RawlogWriter::externalizeImage(mrpt::img::CImage& img, const std::string& file_name) {
  if (!images_dir_made_) {
    std::error_code ec;
    fs::create_directories(images_dir_, ec);
    if (ec) throw InputError("images dir '" + images_dir_ + "': " + ec.message());
    images_dir_made_ = true;
  }
  const std::string full = (fs::path(images_dir_) / file_name).string();
  if (!img.saveToFile(full)) throw InputError("image '" + full + "': cannot be written");
  img.setExternalStorage(file_name);
}

void RawlogWriter::flush() {
  if (!file_) return;
  ar_.reset();
  file_->close();
  std::string err;
  if (!file_->open(path_, gz_level_, err, mrpt::io::OpenMode::APPEND)) {
    file_.reset();
    throw ProcessingError("rawlog '" + path_ + "': cannot reopen to append" +
                          (err.empty() ? "" : " (" + err + ")"));
  }
  ar_ = mrpt::serialization::archiveUniquePtrFrom(*file_);
}

void RawlogWriter::close() {
  ar_.reset();
  if (file_) {
    file_->close();
    file_.reset();
  }
}

// ---------------------------------------------------------------------------------------
RawlogReader::RawlogReader(const std::string& path) : path_(path) {
  registerStarTrackerClasses();
  jpegErrorsThrow();  // a damaged inline JPEG is damage, not exit() (jpeg_errors.hpp)
  mrptAllocationsThrow();  // a matrix of declared gigabytes is damage, not SIGSEGV
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) {
    throw InputError("rawlog '" + path + "': no such file");
  }
  file_ = std::make_unique<mrpt::io::CFileGZInputStream>();
  std::string err;
  if (!file_->open(path, err)) {
    throw InputError("rawlog '" + path + "': cannot open" + (err.empty() ? "" : " (" + err + ")"));
  }
  ar_ = mrpt::serialization::archiveUniquePtrFrom(*file_);
  budget_ = rawlogReadBudget(fs::file_size(path, ec));
  mrpt::img::CImage::setImagesPathBase(rawlogImagesDir(path));
}

RawlogReader::~RawlogReader() = default;

mrpt::obs::CObservation::Ptr RawlogReader::next() {
  if (at_end_) return nullptr;
  const auto where = [&] {
    return "rawlog '" + path_ + "', object " + std::to_string(count_) + ": ";
  };
  mrpt::serialization::CSerializable::Ptr obj;
  try {
    {
      const ReadAllocationBudget budget(budget_);  // a damaged length is damage, not gigabytes
      obj = ar_->ReadObject();
    }
    offset_ = file_->getPosition();
  } catch (const mrpt::serialization::CExceptionEOF&) {
    at_end_ = true;
    // End of file exactly between two objects: the normal end of a rawlog. Any byte of the
    // object read (or a gz stream that cannot say where it is) means the file ends inside the
    // object: truncated, which MRPT reports as the same EOF.
    const std::uint64_t pos = file_->getPosition();
    if (pos == offset_) return nullptr;
    const std::string why =
        pos > offset_ && pos != std::uint64_t(-1)
            ? "the file ends inside the object (" + std::to_string(pos - offset_) +
                  " of its bytes present)"
            : "the file ends inside the object";
    throw RawlogDamageError(where() + "(byte " + std::to_string(offset_) +
                                " of the uncompressed stream) truncated: " + why,
                            count_, offset_, why);
  } catch (const std::bad_alloc&) {
    at_end_ = true;
    std::error_code ec;
    const std::string why = "the object declares more memory than this " +
                            std::to_string(fs::file_size(path_, ec)) +
                            "-byte file can describe (a damaged length; at most " +
                            std::to_string(budget_ >> 20) + " MB read for it)";
    throw RawlogDamageError(where() + "(byte " + std::to_string(offset_) +
                                " of the uncompressed stream) damaged: " + why,
                            count_, offset_, why);
  } catch (const std::exception& e) {
    at_end_ = true;
    // MRPT's message is long (a stack trace); its first line says what went wrong, e.g. a
    // class that is not registered, a truncated object or bytes that are no MRPT object.
    const std::string msg = e.what();
    const std::size_t m = msg.find("Message:");
    std::string first = m == std::string::npos ? msg : msg.substr(m + 8);
    first = first.substr(first.find_first_not_of(' '));
    first = first.substr(0, first.find('\n'));
    // MRPT's "Exception while parsing typed object 'X' from ... for file ...": in words.
    if (first.rfind("Exception while parsing typed object '", 0) == 0) {
      const std::size_t q0 = first.find('\''), q1 = first.find('\'', q0 + 1);
      if (q1 != std::string::npos)
        first = "a " + first.substr(q0 + 1, q1 - q0 - 1) + " object cut short or damaged";
    }
    // "Stored object has class 'X' which is not registered": an unknown class only when X
    // looks like a C++ name; otherwise the bytes where a class name belongs are damaged.
    bool unknown_class = msg.find("not registered") != std::string::npos;
    if (unknown_class) {
      const std::size_t q0 = first.find('\''), q1 = first.rfind('\'');
      const std::string name =
          q0 != std::string::npos && q1 > q0 ? first.substr(q0 + 1, q1 - q0 - 1) : "";
      unknown_class = !name.empty() && std::all_of(name.begin(), name.end(), [](char c) {
        return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == ':';
      });
      if (!unknown_class) first = "bytes that are no MRPT object (a garbled class name)";
    }
    if (unknown_class) {
      throw InputError(where() +
                       "class not registered (a type this program does not know; for "
                       "st::CObservationStarTracker load the startracker_mrpt plugin): " +
                       first);
    }
    throw RawlogDamageError(where() + "(byte " + std::to_string(offset_) +
                                " of the uncompressed stream) truncated or not a rawlog: " +
                                first,
                            count_, offset_, first);
  }
  auto obs = std::dynamic_pointer_cast<mrpt::obs::CObservation>(obj);
  if (!obs) {
    at_end_ = true;
    throw InputError(where() + "a " +
                     std::string(obj ? obj->GetRuntimeClass()->className : "null object") +
                     " is not an observation (only observation-only rawlogs are supported)");
  }
  ++count_;
  return obs;
}

std::vector<mrpt::obs::CObservation::Ptr> readRawlog(const std::string& path) {
  RawlogReader reader(path);
  std::vector<mrpt::obs::CObservation::Ptr> out;
  while (auto obs = reader.next()) out.push_back(std::move(obs));
  return out;
}

std::vector<mrpt::obs::CObservation::Ptr> readRawlogUpToDamage(const std::string& path,
                                                               RawlogDamage* damage) {
  std::vector<mrpt::obs::CObservation::Ptr> out;
  visitRawlogUpToDamage(path, [&out](const mrpt::obs::CObservation::Ptr& o) { out.push_back(o); },
                        damage);
  return out;
}

mrpt::obs::CObservation::Ptr recordingMarker(const std::string& label, const std::string& text,
                                             mrpt::Clock::time_point when) {
  auto c = mrpt::obs::CObservationComment::Create();
  c->sensorLabel = label;
  c->timestamp = when;
  c->text = label + ": " + text;
  return c;
}

bool isRecordingMarker(const mrpt::obs::CObservation& obs, const std::string& label) {
  const auto* c = dynamic_cast<const mrpt::obs::CObservationComment*>(&obs);
  return c && c->text.compare(0, label.size() + 1, label + ":") == 0;
}

std::size_t visitRawlogUpToDamage(
    const std::string& path, const std::function<void(const mrpt::obs::CObservation::Ptr&)>& visit,
    RawlogDamage* damage) {
  RawlogReader reader(path);
  std::size_t n = 0;
  RawlogDamage d;
  try {
    while (auto obs = reader.next()) {
      visit(obs);
      ++n;
    }
  } catch (const RawlogDamageError& e) {
    if (e.object == 0) throw;  // nothing readable: not a rawlog (or cut inside object 0)
    d.damaged = true;
    d.object = e.object;
    d.offset = e.offset;
    d.reason = e.reason;
    d.message = "rawlog '" + path + "': stopped at object " + std::to_string(e.object) +
                " (byte " + std::to_string(e.offset) +
                " of the uncompressed stream), truncated or damaged: " + e.reason + "; the " +
                std::to_string(e.object) + " observations before it are intact";
  }
  if (damage) *damage = d;
  return n;
}

void ExternalImages::add(const mrpt::obs::CObservation& o, const std::string& sensor_label) {
  if (o.sensorLabel != sensor_label) return;
  const auto* io = dynamic_cast<const mrpt::obs::CObservationImage*>(&o);
  if (!io || !io->image.isExternallyStored()) return;
  ++external;
  const std::string file = io->image.getExternalStorageFileAbsolutePath();
  std::error_code ec;
  if (fs::is_regular_file(file, ec)) return;
  if (missing++ == 0) first_missing = file;
}


}  // namespace st

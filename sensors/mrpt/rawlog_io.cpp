#include "sensors/mrpt/rawlog_io.hpp"

#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CObservationImage.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/rtti/CObject.h>
#include <mrpt/serialization/CArchive.h>

#include <filesystem>
#include <mutex>

#include "common/errors.hpp"
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
    : path_(path), images_dir_(rawlogImagesDir(path)) {
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
    obj = ar_->ReadObject();
  } catch (const mrpt::serialization::CExceptionEOF&) {
    // End of file exactly between two objects: the normal end of a rawlog.
    at_end_ = true;
    return nullptr;
  } catch (const std::exception& e) {
    at_end_ = true;
    // MRPT's message is long (a stack trace); its first line says what went wrong, e.g. a
    // class that is not registered, a truncated object or bytes that are no MRPT object.
    const std::string msg = e.what();
    const std::size_t m = msg.find("Message:");
    std::string first = m == std::string::npos ? msg : msg.substr(m + 8);
    first = first.substr(first.find_first_not_of(' '));
    first = first.substr(0, first.find('\n'));
    const bool unknown_class = msg.find("not registered") != std::string::npos;
    throw InputError(where() + (unknown_class
                                    ? "class not registered (a type this program does not "
                                      "know; for st::CObservationStarTracker load the "
                                      "startracker_mrpt plugin): "
                                    : "truncated or not a rawlog: ") +
                     first);
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

ExternalImages checkExternalImages(const std::vector<mrpt::obs::CObservation::Ptr>& obs,
                                   const std::string& sensor_label) {
  ExternalImages r;
  for (const auto& o : obs) {
    if (o->sensorLabel != sensor_label) continue;
    const auto* io = dynamic_cast<const mrpt::obs::CObservationImage*>(o.get());
    if (!io || !io->image.isExternallyStored()) continue;
    ++r.external;
    const std::string file = io->image.getExternalStorageFileAbsolutePath();
    std::error_code ec;
    if (fs::is_regular_file(file, ec)) continue;
    if (r.missing++ == 0) r.first_missing = file;
  }
  return r;
}

}  // namespace st

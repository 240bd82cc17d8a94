// An earlier run's rawlog and images at an output path: kept unless -f (simulate, live).
#include "app/earlier_run.hpp"

#include <filesystem>
#include <system_error>
#include <vector>

#include "common/errors.hpp"
#include "sensors/sim/rawlog_writer.hpp"

namespace st::app {

namespace fs = std::filesystem;

void replaceEarlierRun(const std::string& rawlog, bool force) {
  const fs::path images = externalImagesDir(rawlog);
  std::error_code ec;
  const bool rawlog_exists = fs::exists(rawlog, ec);
  const bool images_link = fs::is_symlink(images, ec);
  const bool images_used =
      images_link || (fs::is_directory(images, ec) && !fs::is_empty(images, ec));
  if (!rawlog_exists && !images_used) return;
  if (!force) {
    throw InputError("-o/--output " + rawlog + ": " +
                     (rawlog_exists ? std::string("the rawlog exists")
                                    : images.string() + " holds images of an earlier run") +
                     "; --force (-f) replaces it and empties " + images.string());
  }
  ec.clear();
  if (images_link) {
    // Only the link: its target is another rawlog's folder (replay -o links the input's).
    fs::remove(images, ec);
  } else if (std::error_code missing; fs::is_directory(images, missing)) {
    // (A rawlog without an images folder has nothing to empty: not an error.)
    std::vector<fs::path> entries;
    for (const auto& entry : fs::directory_iterator(images, ec)) entries.push_back(entry.path());
    for (const fs::path& p : entries) {
      if (ec) break;
      fs::remove_all(p, ec);
    }
  }
  if (ec) throw InputError(images.string() + ": cannot empty the earlier run's images (" +
                           ec.message() + ")");
}

}  // namespace st::app

// Rawlogs (sensors/mrpt/rawlog_io): the reader streams object by object, as replay does,
// through MRPT's deserialization of every class a rawlog may name (ours registered), then
// the up-to-damage reader replay uses. The input is the uncompressed object stream (MRPT's
// gz reader takes plain files too): fuzzing through gzip would mostly fuzz zlib's CRC.
#include <mrpt/img/CImage.h>
#include <mrpt/obs/CObservationImage.h>

#include <sstream>

#include "sensors/mrpt/rawlog_io.hpp"
#include "tests/fuzz/targets/fuzz_io.hpp"

namespace st::fuzz {

int rawlog(const std::uint8_t* data, std::size_t size) {
  const std::string path = writeInput(data, size, ".rawlog");
  refuseOnlyWithInputError(path, [&] {
    RawlogReader reader(path);
    while (auto obs = reader.next()) {
      std::ostringstream text;  // what rawlog-edit --info and RawLogViewer show
      try {
        obs->getDescriptionAsText(text);
      } catch (const mrpt::img::CExceptionExternalImageNotFound&) {
        // A camera frame stored beside the rawlog that is not there: MRPT's own tools stop
        // the same way; not a parser fault.
      }
    }
  });
  refuseOnlyWithInputError(path, [&] {
    RawlogDamage damage;
    const auto kept = readRawlogUpToDamage(path, &damage);
    if (damage.damaged && damage.object != kept.size()) std::abort();  // its documented contract
  });
  return 0;
}

}  // namespace st::fuzz

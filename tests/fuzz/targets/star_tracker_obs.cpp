// CObservationStarTracker deserialization of every serialization version, straight from
// the bytes (the rawlog target reaches it only through a valid object header). The first
// byte picks the version: 0..kCurrentVersion and one beyond, which must be refused.
#include <mrpt/io/CMemoryStream.h>
#include <mrpt/serialization/CArchive.h>

#include <sstream>

#include "sensors/mrpt/observation_star_tracker.hpp"
#include "tests/fuzz/targets/fuzz_io.hpp"

namespace st::fuzz {

namespace {

/// serializeFrom is protected: MRPT calls it from CArchive::ReadObject after the header.
struct Exposed : CObservationStarTracker {
  using CObservationStarTracker::serializeFrom;
};

}  // namespace

int star_tracker_obs(const std::uint8_t* data, std::size_t size) {
  const Split in = splitSelector(data, size);
  const auto version = std::uint8_t(in.selector % (CObservationStarTracker::kCurrentVersion + 2));
  mrpt::io::CMemoryStream mem;
  mem.assignMemoryNotOwn(in.data, in.size);
  auto ar = mrpt::serialization::archiveFrom(mem);
  Exposed obs;
  try {
    obs.serializeFrom(ar, version);
  } catch (const std::exception&) {
    // End of data or an unknown version: RawlogReader turns these into RawlogDamageError.
    return 0;
  }
  std::ostringstream text;
  obs.getDescriptionAsText(text);
  return 0;
}

}  // namespace st::fuzz

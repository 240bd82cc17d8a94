// Writes a star-tracker fix through MRPT's serialization and reads it back as a program that
// only installed the package's `mrpt` component would.
#include <mrpt/io/CMemoryStream.h>
#include <mrpt/serialization/CArchive.h>

#include <cstdio>
#include <startracker/mrpt/observation_star_tracker.hpp>

int main() {
  st::CObservationStarTracker fix;
  fix.mode = st::StarTrackerMode::kTracking;
  fix.stars.resize(1);
  fix.stars[0].catalog_id = 32349;  // Sirius
  mrpt::io::CMemoryStream buf;
  mrpt::serialization::archiveFrom(buf) << fix;
  buf.Seek(0);
  const auto back = mrpt::serialization::archiveFrom(buf).ReadObject<st::CObservationStarTracker>();
  if (!back || back->stars.size() != 1 || back->stars[0].catalog_id != 32349) return 1;
  std::printf("%s round trip: %s, %zu star\n", back->GetRuntimeClass()->className,
              st::toString(back->mode), back->stars.size());
  return 0;
}

#include <gtest/gtest.h>
#include <mrpt/system/datetime.h>
#include <cstdlib>
#include "sensors/mrpt/rawlog_io.hpp"
namespace st {
TEST(ZzMeasure, GyroStops) {
  const char* in_p = std::getenv("ZZ_IN");
  if (!in_p) GTEST_SKIP();
  const double stop = std::atof(std::getenv("ZZ_STOP"));
  const auto in = readRawlog(in_p);
  RawlogWriter w(std::getenv("ZZ_OUT"));
  for (const auto& o : in) {
    const double t = mrpt::system::timeDifference(in.front()->timestamp, o->timestamp);
    if (o->sensorLabel != "GYRO" || t < stop) w.write(*o);
  }
}
}

// Camera files (sensors/camera/camera_model.cpp): the first byte picks OpenCV YAML, OpenCV
// XML or an MRPT .ini with a [camera] section; the rest is the file.
#include "sensors/camera/camera_model.hpp"
#include "tests/fuzz/targets/fuzz_io.hpp"
#include "sensors/mrpt/camera_ini.hpp"

namespace st::fuzz {

int camera(const std::uint8_t* data, std::size_t size) {
  const Split in = splitSelector(data, size);
  static const char* const kSuffix[] = {".yaml", ".xml", ".ini"};
  const unsigned kind = in.selector % 3;
  const std::string path = writeInput(in.data, in.size, kSuffix[kind]);
  refuseOnlyWithInputError(path, [&] {
    const CameraModel cam = kind < 2 ? CameraModel::loadYaml(path) : loadCameraIniFile(path, "camera");
    cameraIniKeys(cam);  // what `startracker config` prints back
  });
  return 0;
}

}  // namespace st::fuzz

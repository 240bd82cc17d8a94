// The image loader (imageio/image_file.cpp): header checks before decoding, then OpenCV or
// cfitsio. The first byte picks the file name's suffix (FITS is chosen by name, the other
// codecs by content): .png .jpg .tif .pgm .fits.
#include "imageio/image_file.hpp"
#include "tests/fuzz/targets/fuzz_io.hpp"

namespace st::fuzz {

int image(const std::uint8_t* data, std::size_t size) {
  const Split in = splitSelector(data, size);
  static const char* const kSuffix[] = {".png", ".jpg", ".tif", ".pgm", ".fits"};
  const std::string path = writeInput(in.data, in.size, kSuffix[in.selector % 5]);
  refuseOnlyWithInputError(path, [&] { imageio::loadImage(path); });
  return 0;
}

}  // namespace st::fuzz

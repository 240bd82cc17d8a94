#include "imageio/opencv/opencv_formats.hpp"

#include <opencv2/imgcodecs.hpp>

#include <new>
#include <string>

#include "common/errors.hpp"
#include "imageio/image_file.hpp"

namespace st::imageio {
namespace {

/// OpenCV logs its own warning for a file it cannot decode; the InputError says it in the
/// project's words. OpenCV's refusal of a header above its own pixel limit (an exception from
/// validateInputImageSize) becomes the project's "too large".
cv::Mat readWithOpenCv(const std::string& path) {
  cv::Mat raw;
  try {
    raw = cv::imread(path, cv::IMREAD_UNCHANGED);
  } catch (const cv::Exception& e) {
    if (e.func.find("validateInputImageSize") != std::string::npos)
      throw InputError(path + ": image too large (its header claims more than " +
                       std::to_string(kMaxImagePixels) + " pixels, the most that are read)");
    raw.release();
  } catch (const std::bad_alloc&) {
    throw InputError(path + ": image too large to decode (out of memory)");
  }
  if (raw.empty()) throw InputError(path + ": cannot read image (PNG, JPEG, TIFF, PGM or FITS)");
  return raw;
}

void writeWithOpenCv(const std::string& path, const cv::Mat& image) {
  bool ok = false;
  try {
    ok = cv::imwrite(path, image);
  } catch (const cv::Exception&) {
    ok = false;
  }
  if (!ok) throw InputError(path + ": cannot write this image format (try .fits, .png or .tif)");
}

}  // namespace

void registerOpenCvFormats() { setOtherFormats({readWithOpenCv, writeWithOpenCv}); }

}  // namespace st::imageio

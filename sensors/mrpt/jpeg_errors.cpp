#include "sensors/mrpt/jpeg_errors.hpp"

#include <dlfcn.h>

#include <cstdio>
#include <stdexcept>
#include <string>

extern "C" {
#include <jpeglib.h>
}

namespace {

[[noreturn]] void throwingErrorExit(j_common_ptr cinfo) {
  char msg[JMSG_LENGTH_MAX] = {};
  (*cinfo->err->format_message)(cinfo, msg);
  throw std::runtime_error(std::string("damaged JPEG image data: ") + msg);
}

using StdError = jpeg_error_mgr* (*)(jpeg_error_mgr*);

StdError libjpegStdError() {
  static const StdError real = reinterpret_cast<StdError>(dlsym(RTLD_NEXT, "jpeg_std_error"));
  return real;
}

}  // namespace

extern "C" jpeg_error_mgr* jpeg_std_error(jpeg_error_mgr* err) {
  const StdError real = libjpegStdError();
  if (!real) {  // no libjpeg behind us: nothing can use the manager anyway
    std::fputs("startracker: libjpeg's jpeg_std_error not found\n", stderr);
    std::abort();
  }
  real(err);
  err->error_exit = throwingErrorExit;
  return err;
}

namespace st {

bool jpegErrorsThrow() { return libjpegStdError() != nullptr; }

}  // namespace st

// The table of imageio/fits.hpp, filled once by dlopen + dlsym.
#define ST_FITS_LOADER  // the real cfitsio names here, not fits.hpp's redirections
#include "imageio/fits.hpp"

#include <dlfcn.h>

#include <mutex>
#include <string>

#include "common/errors.hpp"

namespace st::imageio {
namespace {

FitsApi load() {
  // The soname the headers were built against (fitsio.h's CFITSIO_SONAME).
  const std::string lib = "libcfitsio.so." + std::to_string(CFITSIO_SONAME);
  void* h = ::dlopen(lib.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!h)
    throw InputError("FITS files need " + lib + " (Debian package libcfitsio10): " + ::dlerror());
  FitsApi api;
#define ST_FITS_RESOLVE(name)                                                                 \
  api.name = reinterpret_cast<decltype(&::name)>(::dlsym(h, #name));                          \
  if (!api.name) throw InputError(lib + " has no " #name ": a cfitsio older than the headers");
  ST_FITS_FUNCTIONS(ST_FITS_RESOLVE)
#undef ST_FITS_RESOLVE
  return api;  // the library stays loaded for the process
}

}  // namespace

const FitsApi& fitsApi() {
  static std::once_flag once;
  static FitsApi api;
  std::call_once(once, [] { api = load(); });
  return api;
}

}  // namespace st::imageio

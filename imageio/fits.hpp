/// @file fits.hpp
/// cfitsio, loaded on first use. Include this instead of <fitsio.h>: the fits_* calls are the
/// library's own (its macros), resolved through dlopen("libcfitsio.so.N") when a program first
/// touches a FITS file. libcfitsio pulls curl, GnuTLS and Kerberos (30 shared libraries,
/// ~12 ms at every start measured here): a plate solve of a PNG or TIFF per process must not
/// pay them. A missing library is an InputError naming it, at the first FITS file.
#pragma once
#include <fitsio.h>

// Every cfitsio function the project calls (the names fitsio.h's fits_* macros expand to).
#define ST_FITS_FUNCTIONS(X)                                                                  \
  X(ffgerr) X(ffclos) X(ffgpxv) X(ffgky) X(ffiopn) X(ffgipr) X(ffppr) X(ffgcv) X(fftopn)      \
  X(ffopentest) X(ffmahd) X(ffgnrw) X(ffgiet) X(ffgidm) X(ffgcno) X(ffcrim) X(ffinit)

namespace st::imageio {

struct FitsApi {
#define ST_FITS_POINTER(name) decltype(&::name) name = nullptr;
  ST_FITS_FUNCTIONS(ST_FITS_POINTER)
#undef ST_FITS_POINTER
};

/// The loaded library's functions; InputError when libcfitsio cannot be loaded.
const FitsApi& fitsApi();

}  // namespace st::imageio

// From here on a fits_* call goes through the table (a macro is not expanded again inside
// its own expansion, so the member access keeps its name). fits.cpp, which fills the table,
// sees the real names.
#ifndef ST_FITS_LOADER
#define ffgerr ::st::imageio::fitsApi().ffgerr
#define ffclos ::st::imageio::fitsApi().ffclos
#define ffgpxv ::st::imageio::fitsApi().ffgpxv
#define ffgky ::st::imageio::fitsApi().ffgky
#define ffiopn ::st::imageio::fitsApi().ffiopn
#define ffgipr ::st::imageio::fitsApi().ffgipr
#define ffppr ::st::imageio::fitsApi().ffppr
#define ffgcv ::st::imageio::fitsApi().ffgcv
#define fftopn ::st::imageio::fitsApi().fftopn
#define ffopentest ::st::imageio::fitsApi().ffopentest
#define ffmahd ::st::imageio::fitsApi().ffmahd
#define ffgnrw ::st::imageio::fitsApi().ffgnrw
#define ffgiet ::st::imageio::fitsApi().ffgiet
#define ffgidm ::st::imageio::fitsApi().ffgidm
#define ffgcno ::st::imageio::fitsApi().ffgcno
#define ffcrim ::st::imageio::fitsApi().ffcrim
#define ffinit ::st::imageio::fitsApi().ffinit
#endif  // ST_FITS_LOADER

/// @file jpeg_errors.hpp
/// libjpeg's fatal errors as exceptions. MRPT 2.5 decodes an inline JPEG image of a rawlog
/// (`CImage::loadFromStreamAsJPEG`) with libjpeg's default error manager, whose `error_exit`
/// prints a line and calls exit(): one damaged image ended replay with exit code 1 and no
/// word of which file or object (fuzz finding tests/fuzz/regressions/rawlog/
/// cimage_jpeg_libjpeg_exit). This project defines `jpeg_std_error` (the one call every
/// libjpeg user makes to get that manager; the dynamic linker resolves MRPT's call to the
/// executable's definition first): it fills the manager as libjpeg does and replaces
/// `error_exit` with one that throws std::runtime_error carrying libjpeg's message, which the
/// rawlog reader reports as damage like any other failed read. libjpeg's own frames are
/// unwound (Debian builds them with unwind tables); the decoder state MRPT abandons is the
/// error path's only cost. libjpeg's own documentation asks callers to replace error_exit
/// for exactly this (libjpeg.txt, "Error handling").
#pragma once

namespace st {

/// True once libjpeg's error manager throws; referencing it keeps the definition linked into
/// every program that reads rawlogs (RawlogReader calls it).
bool jpegErrorsThrow();

}  // namespace st

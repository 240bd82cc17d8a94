/// @file image_codecs.cpp
/// Each decoder follows OpenCV 4.6's imgcodecs (grfmt_png/jpeg/tiff/pxm.cpp) for the
/// IMREAD_UNCHANGED case -- same library calls, same colour conversions -- because callers and
/// tests compare against cv::imread bit for bit. It departs from OpenCV only where OpenCV
/// would return a partial or silently wrong image: such files are an InputError here.
///
/// libpng and libjpeg report errors by longjmp. Every function that calls setjmp below owns no
/// object with a destructor (longjmp would skip it) and reads no local it changed after setjmp.
#include "common/output_file.hpp"
#include "imageio/image_codecs.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <climits>
#include <csetjmp>
#include <cstdarg>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <memory>
#include <utility>
#include <vector>

// After <cstdio>: jpeglib.h uses FILE and size_t without including their headers. libtiff's
// deprecated int8..uint64 typedefs would mark OpenCV's own int64/uint64 deprecated.
#define TIFF_DISABLE_DEPRECATED
#include <jerror.h>
#include <jpeglib.h>
#include <png.h>
#include <tiffio.h>
#include <zlib.h>

#include "common/errors.hpp"

namespace st::imageio {
namespace {

constexpr std::uint64_t kMaxPixelBytes = std::uint64_t{1} << 31;

[[noreturn]] void fail(const std::string& path, const std::string& what) {
  throw InputError(path + ": " + what);
}

bool littleEndian() {
  const std::uint16_t one = 1;
  unsigned char first = 0;
  std::memcpy(&first, &one, 1);
  return first == 1;
}

struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};
using File = std::unique_ptr<std::FILE, FileCloser>;

File openForReading(const std::string& path) {
  File file(std::fopen(path.c_str(), "rb"));
  if (!file) fail(path, std::string("cannot open image: ") + std::strerror(errno));
  return file;
}

std::string rowsDecoded(std::uint64_t done, std::uint64_t total) {
  return std::to_string(done) + " of " + std::to_string(total) + " rows decoded";
}

/// The only allocation of the decoded image: its size comes from the file header, which a
/// damaged or hostile file can set to anything.
cv::Mat allocate(const std::string& path, std::uint64_t width, std::uint64_t height, int type) {
  const std::string size = std::to_string(width) + "x" + std::to_string(height);
  if (width < 1 || height < 1) fail(path, "image has no pixels (" + size + ")");
  const auto pixel_bytes = static_cast<std::uint64_t>(CV_ELEM_SIZE(type));
  if (width > INT_MAX || height > INT_MAX || width * height > kMaxPixelBytes / pixel_bytes) {
    fail(path, "image too large: " + size + " with " + std::to_string(pixel_bytes) +
                   " bytes per pixel is over 2 GiB");
  }
  return cv::Mat(static_cast<int>(height), static_cast<int>(width), type);
}

Format formatOf(const unsigned char* magic, std::size_t size) {
  static const unsigned char kPng[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (size >= 8 && std::memcmp(magic, kPng, 8) == 0) return Format::kPng;
  if (size >= 3 && magic[0] == 0xff && magic[1] == 0xd8 && magic[2] == 0xff) return Format::kJpeg;
  if (size >= 4) {
    // Classic TIFF (42) and BigTIFF (43), either byte order.
    const bool intel =
        magic[0] == 'I' && magic[1] == 'I' && (magic[2] == 42 || magic[2] == 43) && magic[3] == 0;
    const bool motorola =
        magic[0] == 'M' && magic[1] == 'M' && magic[2] == 0 && (magic[3] == 42 || magic[3] == 43);
    if (intel || motorola) return Format::kTiff;
  }
  if (size >= 3 && magic[0] == 'P' && (magic[1] == '5' || magic[1] == '6') &&
      std::isspace(magic[2])) {
    return Format::kPnm;
  }
  return Format::kOther;
}

Format formatOf(std::FILE* file) {
  unsigned char magic[8] = {};
  return formatOf(magic, std::fread(magic, 1, sizeof magic, file));
}

// ------------------------------------------------------------------------------------ JPEG

struct JpegErrors {
  jpeg_error_mgr pub;  // first member: libjpeg hands the callbacks a jpeg_error_mgr*
  std::jmp_buf jump;
  bool data_ran_out;
  char message[JMSG_LENGTH_MAX];
};

void jpegErrorExit(j_common_ptr cinfo) {
  auto* errors = reinterpret_cast<JpegErrors*>(cinfo->err);
  (*cinfo->err->format_message)(cinfo, errors->message);
  std::longjmp(errors->jump, 1);
}

/// libjpeg only warns when the data ends early (the file, or the entropy-coded segment), and
/// pads the rest of the image with grey: those warnings must stop decoding like errors. The
/// others (extraneous bytes, a bad Huffman code) concern damage within a complete image;
/// OpenCV ignores them, and so does this reader.
void jpegEmitMessage(j_common_ptr cinfo, int level) {
  if (level >= 0) return;  // trace messages
  const int code = cinfo->err->msg_code;
  if (code == JWRN_JPEG_EOF || code == JWRN_HIT_MARKER) {
    reinterpret_cast<JpegErrors*>(cinfo->err)->data_ran_out = code == JWRN_JPEG_EOF;
    jpegErrorExit(cinfo);
  }
  ++cinfo->err->num_warnings;
}

void jpegOutputMessage(j_common_ptr) {}  // the default prints to stderr

struct JpegDecoder {
  jpeg_decompress_struct cinfo{};  // zeroed: jpeg_destroy is then safe even if create failed
  JpegErrors errors{};
  JpegDecoder() {
    cinfo.err = jpeg_std_error(&errors.pub);
    errors.pub.error_exit = jpegErrorExit;
    errors.pub.emit_message = jpegEmitMessage;
    errors.pub.output_message = jpegOutputMessage;
  }
  ~JpegDecoder() { jpeg_destroy_decompress(&cinfo); }
  JpegDecoder(const JpegDecoder&) = delete;
  JpegDecoder& operator=(const JpegDecoder&) = delete;
};

bool jpegReadHeader(JpegDecoder* d, const unsigned char* data, std::size_t size) {
  if (setjmp(d->errors.jump)) return false;
  jpeg_create_decompress(&d->cinfo);
  jpeg_mem_src(&d->cinfo, data, static_cast<unsigned long>(size));
  jpeg_read_header(&d->cinfo, TRUE);
  return true;
}

/// OpenCV's icvCvt_CMYK2BGR_8u_C4C3R (Adobe's inverted CMYK, as libjpeg returns it).
void cmykToBgr(const unsigned char* cmyk, unsigned char* bgr, int width) {
  for (int x = 0; x < width; ++x, cmyk += 4, bgr += 3) {
    const int k = cmyk[3];
    bgr[2] = static_cast<unsigned char>(k - ((255 - cmyk[0]) * k >> 8));
    bgr[1] = static_cast<unsigned char>(k - ((255 - cmyk[1]) * k >> 8));
    bgr[0] = static_cast<unsigned char>(k - ((255 - cmyk[2]) * k >> 8));
  }
}

/// cmyk_row: scratch row for 4-component files, null otherwise.
bool jpegReadPixels(JpegDecoder* d, cv::Mat* image, unsigned char* cmyk_row) {
  if (setjmp(d->errors.jump)) return false;
  jpeg_decompress_struct* cinfo = &d->cinfo;
  jpeg_start_decompress(cinfo);
  const int components = cmyk_row != nullptr ? 4 : image->channels();
  if (cinfo->output_width != static_cast<JDIMENSION>(image->cols) ||
      cinfo->output_height != static_cast<JDIMENSION>(image->rows) ||
      cinfo->output_components != components) {
    std::snprintf(d->errors.message, sizeof d->errors.message,
                  "libjpeg output layout differs from the header");
    return false;
  }
  while (cinfo->output_scanline < cinfo->output_height) {
    const int y = static_cast<int>(cinfo->output_scanline);
    JSAMPROW row = cmyk_row != nullptr ? cmyk_row : image->ptr(y);
    if (jpeg_read_scanlines(cinfo, &row, 1) != 1) {
      std::snprintf(d->errors.message, sizeof d->errors.message, "libjpeg returned no row");
      return false;
    }
    if (cmyk_row != nullptr) cmykToBgr(cmyk_row, image->ptr(y), image->cols);
  }
  jpeg_finish_decompress(cinfo);
  return true;
}

cv::Mat decodeJpeg(const std::string& path, std::FILE* file) {
  // Decoding from memory makes the end of the data explicit to libjpeg.
  std::vector<unsigned char> data;
  unsigned char chunk[1 << 16];
  for (std::size_t n; (n = std::fread(chunk, 1, sizeof chunk, file)) > 0;) {
    data.insert(data.end(), chunk, chunk + n);
  }
  if (std::ferror(file)) fail(path, std::string("read error: ") + std::strerror(errno));

  JpegDecoder d;
  if (!jpegReadHeader(&d, data.data(), data.size())) {
    fail(path, std::string("not a readable JPEG (libjpeg: ") + d.errors.message + ")");
  }
  // As OpenCV: grey stays grey, everything else becomes BGR; 4 components are CMYK/YCCK.
  // Defaults kept as OpenCV keeps them (JDCT_ISLOW, fancy upsampling): they set the pixels.
  jpeg_decompress_struct& cinfo = d.cinfo;
  const bool cmyk = cinfo.num_components == 4;
  cinfo.out_color_space = cinfo.num_components == 1 ? JCS_GRAYSCALE : cmyk ? JCS_CMYK : JCS_EXT_BGR;
  cv::Mat image = allocate(path, cinfo.image_width, cinfo.image_height,
                           cinfo.num_components == 1 ? CV_8UC1 : CV_8UC3);
  std::vector<unsigned char> cmyk_row(cmyk ? 4 * static_cast<std::size_t>(image.cols) : 0);
  if (!jpegReadPixels(&d, &image, cmyk ? cmyk_row.data() : nullptr)) {
    const std::string rows = rowsDecoded(cinfo.output_scanline, cinfo.output_height);
    if (d.errors.data_ran_out) {
      fail(path, "truncated: " + rows + " (libjpeg: " + d.errors.message + ")");
    }
    fail(path, "corrupt JPEG: " + rows + " (libjpeg: " + d.errors.message + ")");
  }
  return image;
}

// ------------------------------------------------------------------------------------- PNG

struct PngState {
  char message[256];
  png_uint_32 next_row;  // progress, for the error message
  int pass;
};

void pngError(png_structp png, png_const_charp message) {
  auto* state = static_cast<PngState*>(png_get_error_ptr(png));
  std::snprintf(state->message, sizeof state->message, "%s", message);
  png_longjmp(png, 1);
}

void pngWarning(png_structp, png_const_charp) {}  // the default prints to stderr

void pngRowDone(png_structp png, png_uint_32 next_row, int pass) {
  auto* state = static_cast<PngState*>(png_get_error_ptr(png));
  state->next_row = next_row;
  state->pass = pass;
}

struct PngReader {
  PngState state{};
  png_structp png = nullptr;
  png_infop info = nullptr;
  png_infop end = nullptr;
  PngReader() {
    png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &state, pngError, pngWarning);
    if (png != nullptr) {
      info = png_create_info_struct(png);
      end = png_create_info_struct(png);
    }
  }
  ~PngReader() { png_destroy_read_struct(&png, &info, &end); }
  PngReader(const PngReader&) = delete;
  PngReader& operator=(const PngReader&) = delete;
};

bool pngReadHeader(PngReader* r, std::FILE* file) {
  if (setjmp(png_jmpbuf(r->png))) return false;
  png_init_io(r->png, file);
  png_set_read_status_fn(r->png, pngRowDone);
  png_read_info(r->png, r->info);
  return true;
}

/// OpenCV 4.6 PngDecoder::readData's transformations for IMREAD_UNCHANGED, where the output
/// type is what pngType() gives: alpha only when the file has it (channel or tRNS), grey only
/// when the file is grey, native byte order for 16 bits.
bool pngReadPixels(PngReader* r, int color_type, int bit_depth, cv::Mat* image, png_bytepp rows) {
  if (setjmp(png_jmpbuf(r->png))) return false;
  png_structp png = r->png;
  if (bit_depth == 16 && littleEndian()) png_set_swap(png);
  if (image->channels() < 4) {
    png_set_strip_alpha(png);
  } else {
    png_set_tRNS_to_alpha(png);
  }
  if (color_type == PNG_COLOR_TYPE_PALETTE) png_set_palette_to_rgb(png);
  if ((color_type & PNG_COLOR_MASK_COLOR) == 0 && bit_depth < 8) {
    png_set_expand_gray_1_2_4_to_8(png);
  }
  if ((color_type & PNG_COLOR_MASK_COLOR) != 0 && image->channels() > 1) {
    png_set_bgr(png);
  } else if (image->channels() > 1) {
    png_set_gray_to_rgb(png);
  }
  png_set_interlace_handling(png);
  png_read_update_info(png, r->info);
  // Guards the row buffers against a disagreement between pngType() and libpng.
  if (png_get_rowbytes(png, r->info) != image->cols * image->elemSize()) {
    png_error(png, "row size after transformations differs from the expected image type");
  }
  png_read_image(png, rows);
  png_read_end(png, r->end);
  return true;
}

int pngType(int color_type, int bit_depth, bool has_trns) {
  int channels = 1;
  switch (color_type) {
    case PNG_COLOR_TYPE_RGB:
    case PNG_COLOR_TYPE_PALETTE:
      channels = has_trns ? 4 : 3;
      break;
    case PNG_COLOR_TYPE_GRAY_ALPHA:  // grey + alpha becomes BGRA, as in OpenCV
    case PNG_COLOR_TYPE_RGB_ALPHA:
      channels = 4;
      break;
    default:
      channels = 1;  // grey; a grey tRNS is dropped, as in OpenCV
  }
  return CV_MAKETYPE(bit_depth == 16 ? CV_16U : CV_8U, channels);
}

cv::Mat decodePng(const std::string& path, std::FILE* file) {
  PngReader r;
  if (r.png == nullptr || r.info == nullptr || r.end == nullptr) {
    fail(path, "libpng could not be initialised");
  }
  if (!pngReadHeader(&r, file)) {
    fail(path, std::string(std::feof(file) ? "truncated" : "corrupt") +
                   " PNG header (libpng: " + r.state.message + ")");
  }
  png_uint_32 width = 0;
  png_uint_32 height = 0;
  int bit_depth = 0;
  int color_type = 0;
  int interlace = 0;
  png_get_IHDR(r.png, r.info, &width, &height, &bit_depth, &color_type, &interlace, nullptr,
               nullptr);
  const bool has_trns = png_get_valid(r.png, r.info, PNG_INFO_tRNS) != 0;
  cv::Mat image = allocate(path, width, height, pngType(color_type, bit_depth, has_trns));
  std::vector<png_bytep> rows(height);
  for (png_uint_32 y = 0; y < height; ++y) rows[y] = image.ptr(static_cast<int>(y));
  if (!pngReadPixels(&r, color_type, bit_depth, &image, rows.data())) {
    std::string where = rowsDecoded(r.state.next_row, height);
    if (interlace != PNG_INTERLACE_NONE) {
      where = "interlace pass " + std::to_string(r.state.pass + 1) + " of 7, " + where;
    }
    fail(path, std::string(std::feof(file) ? "truncated: " : "corrupt PNG: ") + where +
                   " (libpng: " + r.state.message + ")");
  }
  return image;
}

// ------------------------------------------------------------------------------------ TIFF

/// libtiff's first error for one open file. libtiff sometimes reports an error and carries
/// on with a damaged strip, so any error at all fails the decode.
struct TiffMessages {
  char error[512];
};

int tiffError(TIFF*, void* user_data, const char* module, const char* fmt, va_list ap) {
  auto* messages = static_cast<TiffMessages*>(user_data);
  if (messages->error[0] == '\0') {
    char text[400];
    std::vsnprintf(text, sizeof text, fmt, ap);
    std::snprintf(messages->error, sizeof messages->error, "%s%s%s",
                  module != nullptr ? module : "", module != nullptr ? ": " : "", text);
  }
  return 1;  // handled: nothing reaches libtiff's global (stderr) handler
}

int tiffWarning(TIFF*, void*, const char*, const char*, va_list) { return 1; }

struct TiffCloser {
  void operator()(TIFF* tif) const { TIFFClose(tif); }
};

/// Which of OpenCV 4.6's TIFF paths a file takes, when this reader supports it.
enum class TiffPath {
  kRgba8,   // any layout libtiff's RGBA interface reads (palette, YCbCr, 1-bit, ...) -> 8 bits
  kRaw16,   // 16-bit grey or RGB(A), contiguous samples, copied as stored
  kRaw32F,  // 32-bit float grey
};

struct TiffLayout {
  std::uint32_t width = 0;
  std::uint32_t height = 0;
  std::uint16_t photometric = 0;
  std::uint16_t bits = 0;
  std::uint16_t samples = 0;
  std::uint16_t sample_format = SAMPLEFORMAT_UINT;
  std::uint16_t planar = PLANARCONFIG_CONTIG;
  std::uint16_t orientation = ORIENTATION_TOPLEFT;
  bool tiled = false;
  std::uint32_t block_width = 0;   // tile width, or the image width for strips
  std::uint32_t block_height = 0;  // tile height, or rows per strip
  TiffPath path = TiffPath::kRgba8;
  int type = 0;
};

std::string describe(const TiffLayout& t) {
  const char* format = t.sample_format == SAMPLEFORMAT_UINT     ? "unsigned"
                       : t.sample_format == SAMPLEFORMAT_INT    ? "signed"
                       : t.sample_format == SAMPLEFORMAT_IEEEFP ? "float"
                                                                : "other-format";
  return std::to_string(t.bits) + "-bit " + format + " samples, " + std::to_string(t.samples) +
         " per pixel, photometric " + std::to_string(t.photometric) +
         (t.planar == PLANARCONFIG_SEPARATE ? ", separate planes" : "") + ", orientation " +
         std::to_string(t.orientation);
}

/// OpenCV 4.6 TiffDecoder::readHeader's choice of type, restricted to the layouts whose
/// pixels this reader reproduces; the rest are refused rather than guessed.
TiffLayout tiffLayout(const std::string& path, TIFF* tif) {
  TiffLayout t;
  if (!TIFFGetField(tif, TIFFTAG_IMAGEWIDTH, &t.width) ||
      !TIFFGetField(tif, TIFFTAG_IMAGELENGTH, &t.height)) {
    fail(path, "TIFF without image width or length");
  }
  if (!TIFFGetField(tif, TIFFTAG_PHOTOMETRIC, &t.photometric)) {
    fail(path, "TIFF without photometric interpretation");
  }
  const bool grey =
      t.photometric == PHOTOMETRIC_MINISBLACK || t.photometric == PHOTOMETRIC_MINISWHITE;
  if (!TIFFGetField(tif, TIFFTAG_BITSPERSAMPLE, &t.bits)) t.bits = 1;  // bilevel may omit it
  if (!TIFFGetField(tif, TIFFTAG_SAMPLESPERPIXEL, &t.samples)) t.samples = grey ? 1 : 3;
  TIFFGetField(tif, TIFFTAG_SAMPLEFORMAT, &t.sample_format);
  TIFFGetField(tif, TIFFTAG_PLANARCONFIG, &t.planar);
  TIFFGetField(tif, TIFFTAG_ORIENTATION, &t.orientation);
  t.tiled = TIFFIsTiled(tif) != 0;
  if (t.tiled) {
    if (!TIFFGetField(tif, TIFFTAG_TILEWIDTH, &t.block_width) ||
        !TIFFGetField(tif, TIFFTAG_TILELENGTH, &t.block_height) || t.block_width == 0 ||
        t.block_height == 0) {
      fail(path, "tiled TIFF without a valid tile size");
    }
  } else {
    t.block_width = t.width;
    if (!TIFFGetField(tif, TIFFTAG_ROWSPERSTRIP, &t.block_height) || t.block_height == 0 ||
        t.block_height > t.height) {
      t.block_height = t.height;
    }
  }

  // OpenCV reads any deeper layout it does not know as 8-bit RGBA.
  const bool opencv_reads_as_8bit =
      t.bits > 8 &&
      (t.photometric > PHOTOMETRIC_RGB || (t.samples != 1 && t.samples != 3 && t.samples != 4));
  const std::uint16_t bits = opencv_reads_as_8bit ? 8 : t.bits;
  // OpenCV 4.6 flips other orientations its own way; sky frames are top-left anyway. LogLuv is
  // OpenCV's float HDR path.
  const bool unsupported = t.orientation != ORIENTATION_TOPLEFT ||
                           t.photometric == PHOTOMETRIC_LOGLUV || t.photometric == PHOTOMETRIC_LOGL;
  const int rgba_channels = grey ? 1 : t.photometric == PHOTOMETRIC_PALETTE ? 3 : t.samples;
  if ((bits == 1 || bits == 8) && t.sample_format == SAMPLEFORMAT_UINT &&
      (rgba_channels == 1 || rgba_channels == 3 || rgba_channels == 4) && !unsupported) {
    t.path = TiffPath::kRgba8;
    t.type = CV_MAKETYPE(CV_8U, rgba_channels);
  } else if (bits == 16 && t.sample_format == SAMPLEFORMAT_UINT &&
             t.planar == PLANARCONFIG_CONTIG && !unsupported &&
             ((t.photometric == PHOTOMETRIC_MINISBLACK && t.samples == 1) ||
              (t.photometric == PHOTOMETRIC_RGB && (t.samples == 3 || t.samples == 4)))) {
    // Not MINISWHITE: OpenCV returns those samples uninverted, a negative of the scene.
    t.path = TiffPath::kRaw16;
    t.type = CV_MAKETYPE(CV_16U, t.samples);
  } else if (bits == 32 && t.sample_format == SAMPLEFORMAT_IEEEFP &&
             t.photometric == PHOTOMETRIC_MINISBLACK && t.samples == 1 && !unsupported) {
    t.path = TiffPath::kRaw32F;
    t.type = CV_32FC1;
  } else {
    fail(path, "unsupported TIFF layout: " + describe(t));
  }
  return t;
}

/// OpenCV's conversions of libtiff's packed RGBA pixels to grey, BGR or BGRA.
void rgbaToOutput(const std::uint32_t* rgba, unsigned char* out, int width, int channels) {
  // OpenCV's grey weights (icvCvt_BGRA2Gray_8u_C4C1R): exact for R == G == B.
  constexpr std::uint32_t kShift = 14;
  constexpr auto kRed = static_cast<std::uint32_t>(0.299 * (1 << kShift) + 0.5);
  constexpr auto kGreen = static_cast<std::uint32_t>(0.587 * (1 << kShift) + 0.5);
  constexpr std::uint32_t kBlue = (1 << kShift) - kRed - kGreen;
  for (int x = 0; x < width; ++x) {
    const std::uint32_t p = rgba[x];
    if (channels == 1) {
      *out++ = static_cast<unsigned char>(
          (TIFFGetR(p) * kRed + TIFFGetG(p) * kGreen + TIFFGetB(p) * kBlue + (1 << (kShift - 1))) >>
          kShift);
    } else {
      *out++ = static_cast<unsigned char>(TIFFGetB(p));
      *out++ = static_cast<unsigned char>(TIFFGetG(p));
      *out++ = static_cast<unsigned char>(TIFFGetR(p));
      if (channels == 4) *out++ = static_cast<unsigned char>(TIFFGetA(p));
    }
  }
}

/// Copies one decoded strip or tile (block_width samples per row) into the image,
/// swapping RGB(A) to BGR(A) as OpenCV does.
template <class T>
void copyBlock(const T* block, std::uint32_t block_width, int rows, int x0, int y0, int cols,
               cv::Mat* image) {
  const int channels = image->channels();
  for (int i = 0; i < rows; ++i) {
    const T* src = block + static_cast<std::size_t>(i) * block_width * channels;
    T* dst = image->ptr<T>(y0 + i) + static_cast<std::size_t>(x0) * channels;
    if (channels == 1) {
      std::memcpy(dst, src, sizeof(T) * cols);
      continue;
    }
    for (int x = 0; x < cols; ++x, src += channels, dst += channels) {
      dst[0] = src[2];
      dst[1] = src[1];
      dst[2] = src[0];
      if (channels == 4) dst[3] = src[3];
    }
  }
}

cv::Mat decodeTiff(const std::string& path) {
  TiffMessages messages{};
  std::unique_ptr<TIFFOpenOptions, void (*)(TIFFOpenOptions*)> options(TIFFOpenOptionsAlloc(),
                                                                       TIFFOpenOptionsFree);
  if (!options) fail(path, "libtiff could not be initialised");
  TIFFOpenOptionsSetErrorHandlerExtR(options.get(), tiffError, &messages);
  TIFFOpenOptionsSetWarningHandlerExtR(options.get(), tiffWarning, nullptr);
  // Memory-mapped, as OpenCV reads it: libtiff 4.5's RGBA reader fails on uncompressed tiles
  // of a file opened with "rm" ("Invalid tile byte count").
  std::unique_ptr<TIFF, TiffCloser> tif(TIFFOpenExt(path.c_str(), "r", options.get()));
  if (!tif) fail(path, std::string("not a readable TIFF (libtiff: ") + messages.error + ")");
  messages.error[0] = '\0';  // what libtiff tolerated in the header; the pixels are checked below

  const TiffLayout t = tiffLayout(path, tif.get());
  cv::Mat image = allocate(path, t.width, t.height, t.type);
  const int width = image.cols;
  const int height = image.rows;
  if (t.path == TiffPath::kRgba8) {
    char why[1024] = "";
    if (!TIFFRGBAImageOK(tif.get(), why)) {
      fail(path, "unsupported TIFF layout: " + describe(t) + " (libtiff: " + why + ")");
    }
  }
  const std::size_t block_pixels = static_cast<std::size_t>(t.block_width) * t.block_height;
  const std::size_t block_bytes =
      t.path == TiffPath::kRgba8 ? block_pixels * 4
                                 : static_cast<std::size_t>(t.tiled ? TIFFTileSize64(tif.get())
                                                                    : TIFFStripSize64(tif.get()));
  const std::size_t expected_bytes =
      block_pixels * (t.path == TiffPath::kRgba8 ? 4 : image.elemSize());
  if (block_bytes != expected_bytes || block_bytes > kMaxPixelBytes) {
    fail(path, "unsupported TIFF layout: " + describe(t) + " (unexpected strip or tile size)");
  }
  // 32-bit words: aligned for the RGBA pixels, the 16-bit and the float samples alike.
  std::vector<std::uint32_t> block((block_bytes + 3) / 4);

  // 64-bit steps: a tile may be nearly as large as the image, y + tile height overflow int.
  for (std::int64_t y = 0; y < height; y += t.block_height) {
    const int rows = static_cast<int>(std::min<std::int64_t>(t.block_height, height - y));
    for (std::int64_t x = 0; x < width; x += t.block_width) {
      const int cols = static_cast<int>(std::min<std::int64_t>(t.block_width, width - x));
      const auto x0 = static_cast<std::uint32_t>(x);
      const auto y0 = static_cast<std::uint32_t>(y);
      bool ok = false;
      if (t.path == TiffPath::kRgba8) {
        // stop_on_error = 1: by default libtiff fills an unreadable block with garbage and
        // reports success. The RGBA raster comes bottom-up, a whole tile even at the edges.
        ok = t.tiled ? TIFFReadRGBATileExt(tif.get(), x0, y0, block.data(), 1) != 0
                     : TIFFReadRGBAStripExt(tif.get(), y0, block.data(), 1) != 0;
        const int raster_rows = t.tiled ? static_cast<int>(t.block_height) : rows;
        for (int i = 0; ok && i < rows; ++i) {
          rgbaToOutput(block.data() + static_cast<std::size_t>(raster_rows - 1 - i) * t.block_width,
                       image.ptr(static_cast<int>(y) + i) + x0 * image.elemSize(), cols,
                       image.channels());
        }
      } else {
        const auto size = static_cast<tmsize_t>(block_bytes);
        ok = (t.tiled ? TIFFReadEncodedTile(tif.get(), TIFFComputeTile(tif.get(), x0, y0, 0, 0),
                                            block.data(), size)
                      : TIFFReadEncodedStrip(tif.get(), TIFFComputeStrip(tif.get(), y0, 0),
                                             block.data(), size)) >= 0;
        if (ok && t.path == TiffPath::kRaw16) {
          copyBlock(reinterpret_cast<const std::uint16_t*>(block.data()), t.block_width, rows,
                    static_cast<int>(x), static_cast<int>(y), cols, &image);
        } else if (ok) {
          copyBlock(reinterpret_cast<const float*>(block.data()), t.block_width, rows,
                    static_cast<int>(x), static_cast<int>(y), cols, &image);
        }
      }
      if (!ok || messages.error[0] != '\0') {
        fail(path, "truncated or corrupt: " + rowsDecoded(static_cast<std::uint64_t>(y), height) +
                       " (libtiff: " + (messages.error[0] ? messages.error : "read failed") + ")");
      }
    }
  }
  return image;
}

// ------------------------------------------------------------------------------------- PNM

/// The next header number, after whitespace and '#' comments (to the end of the line), as
/// OpenCV's PxM reader reads it.
std::uint32_t pnmNumber(const std::string& path, std::FILE* file, const char* what) {
  int c = std::fgetc(file);
  for (;;) {
    if (c == '#') {
      while (c != '\n' && c != '\r' && c != EOF) c = std::fgetc(file);
    } else if (c != EOF && std::isspace(c)) {
      c = std::fgetc(file);
    } else {
      break;
    }
  }
  if (c == EOF || !std::isdigit(c)) fail(path, std::string("bad PNM header: no ") + what);
  std::uint64_t value = 0;
  for (; c != EOF && std::isdigit(c); c = std::fgetc(file)) {
    value = value * 10 + static_cast<std::uint64_t>(c - '0');
    if (value > INT_MAX) fail(path, std::string("bad PNM header: ") + what + " too large");
  }
  // The single whitespace byte after the number belongs to the header.
  if (c == EOF || !std::isspace(c)) {
    fail(path, std::string("bad PNM header: no whitespace after ") + what);
  }
  return static_cast<std::uint32_t>(value);
}

cv::Mat decodePnm(const std::string& path, std::FILE* file) {
  char magic[2] = {};
  if (std::fread(magic, 1, 2, file) != 2) fail(path, "truncated PNM header");
  const int channels = magic[1] == '6' ? 3 : 1;
  const std::uint32_t width = pnmNumber(path, file, "width");
  const std::uint32_t height = pnmNumber(path, file, "height");
  const std::uint32_t maxval = pnmNumber(path, file, "maxval");
  if (maxval < 1 || maxval > 65535) {
    fail(path, "bad PNM header: maxval " + std::to_string(maxval) + " outside 1..65535");
  }
  const bool wide = maxval > 255;  // two bytes per sample, big-endian in the file
  cv::Mat image = allocate(path, width, height, CV_MAKETYPE(wide ? CV_16U : CV_8U, channels));
  const std::size_t row_bytes = image.cols * image.elemSize();
  const bool swap_bytes = wide && littleEndian();
  for (int y = 0; y < image.rows; ++y) {
    unsigned char* row = image.ptr(y);
    if (std::fread(row, 1, row_bytes, file) != row_bytes) {
      fail(path, "truncated: " + rowsDecoded(static_cast<std::uint64_t>(y), height));
    }
    if (swap_bytes) {
      for (std::size_t i = 0; i < row_bytes; i += 2) std::swap(row[i], row[i + 1]);
    }
    if (channels == 3) {
      const std::size_t sample = wide ? 2 : 1;
      for (std::size_t i = 0; i < row_bytes; i += 3 * sample) {
        std::swap_ranges(row + i, row + i + sample, row + i + 2 * sample);  // RGB -> BGR
      }
    }
  }
  return image;
}

// ------------------------------------------------------------------------------- PNG write

struct PngWriter {
  PngState state{};
  png_structp png = nullptr;
  png_infop info = nullptr;
  PngWriter() {
    png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &state, pngError, pngWarning);
    if (png != nullptr) info = png_create_info_struct(png);
  }
  ~PngWriter() { png_destroy_write_struct(&png, &info); }
  PngWriter(const PngWriter&) = delete;
  PngWriter& operator=(const PngWriter&) = delete;
};

/// OpenCV 4.6 PngEncoder::write with default parameters: SUB filter, zlib level 1, RLE
/// strategy (fast, and the same bytes as cv::imwrite).
bool pngWrite(PngWriter* w, std::FILE* file, const cv::Mat* image, png_bytepp rows) {
  if (setjmp(png_jmpbuf(w->png))) return false;
  png_structp png = w->png;
  png_init_io(png, file);
  png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_SUB);
  png_set_compression_level(png, Z_BEST_SPEED);
  png_set_compression_strategy(png, Z_RLE);
  const int channels = image->channels();
  png_set_IHDR(png, w->info, static_cast<png_uint_32>(image->cols),
               static_cast<png_uint_32>(image->rows), image->depth() == CV_8U ? 8 : 16,
               channels == 1   ? PNG_COLOR_TYPE_GRAY
               : channels == 3 ? PNG_COLOR_TYPE_RGB
                               : PNG_COLOR_TYPE_RGB_ALPHA,
               PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, w->info);
  png_set_bgr(png);
  if (littleEndian()) png_set_swap(png);
  png_write_image(png, rows);
  png_write_end(png, w->info);
  return true;
}

}  // namespace

Format sniffFormat(const std::string& path) { return formatOf(openForReading(path).get()); }

std::optional<cv::Mat> decode(const std::string& path) {
  const File file = openForReading(path);
  const Format format = formatOf(file.get());
  if (format == Format::kOther) return std::nullopt;
  if (format == Format::kTiff) return decodeTiff(path);
  std::rewind(file.get());
  switch (format) {
    case Format::kPng:
      return decodePng(path, file.get());
    case Format::kJpeg:
      return decodeJpeg(path, file.get());
    default:
      return decodePnm(path, file.get());
  }
}

void writePng(const std::string& path, const cv::Mat& image) {
  const int depth = image.depth();
  const int channels = image.channels();
  if (image.empty() || (depth != CV_8U && depth != CV_16U) ||
      (channels != 1 && channels != 3 && channels != 4)) {
    fail(path, "cannot write as PNG an image of type " + cv::typeToString(image.type()) +
                   (image.empty() ? " (empty)" : "") + "; 8/16-bit, 1/3/4 channels expected");
  }
  std::vector<png_bytep> rows(static_cast<std::size_t>(image.rows));
  // libpng does not write through the row pointers; it takes them as non-const.
  for (int y = 0; y < image.rows; ++y) rows[y] = const_cast<png_bytep>(image.ptr(y));

  PendingOutput out(path);  // under its real name only once complete
  File file(std::fopen(out.tempPath().c_str(), "wb"));
  if (!file) fail(path, std::string("cannot open for writing: ") + std::strerror(errno));
  std::string error;
  {
    PngWriter w;
    if (w.png == nullptr || w.info == nullptr) {
      error = "libpng could not be initialised";
    } else if (!pngWrite(&w, file.get(), &image, rows.data())) {
      error = std::string("PNG write failed (libpng: ") + w.state.message + ")";
    }
  }
  const bool closed = std::fclose(file.release()) == 0;
  if (error.empty() && !closed) error = std::string("write failed: ") + std::strerror(errno);
  if (!error.empty()) fail(path, error);  // the temporary goes with `out`
  out.commit();
}

}  // namespace st::imageio

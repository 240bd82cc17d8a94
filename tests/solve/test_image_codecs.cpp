// solve/image_codecs: the solve path's own image readers must return exactly what
// cv::imread(path, IMREAD_UNCHANGED) returns (OpenCV is the oracle here, and only here), and
// must turn every damaged file into an InputError naming it, silently.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <string>
#include <vector>

#include "imageio/image_codecs.hpp"

// After <cstdio>: jpeglib.h uses FILE and size_t without including their headers. libtiff's
// deprecated int8..uint64 typedefs would mark OpenCV's own int64/uint64 deprecated.
#define TIFF_DISABLE_DEPRECATED
#include <jpeglib.h>
#include <png.h>
#include <tiffio.h>

#include "common/errors.hpp"

namespace st::imageio {
namespace {

namespace fs = std::filesystem;

// ----------------------------------------------------------------------------- helpers

/// Type, size, and every byte of every row.
testing::AssertionResult identical(const cv::Mat& a, const cv::Mat& b) {
  if (a.type() != b.type() || a.size() != b.size()) {
    return testing::AssertionFailure()
           << cv::typeToString(a.type()) << " " << a.cols << "x" << a.rows << " vs "
           << cv::typeToString(b.type()) << " " << b.cols << "x" << b.rows;
  }
  const std::size_t row_bytes = a.cols * a.elemSize();
  for (int y = 0; y < a.rows; ++y) {
    if (std::memcmp(a.ptr(y), b.ptr(y), row_bytes) != 0) {
      return testing::AssertionFailure() << "row " << y << " differs; max abs difference "
                                         << cv::norm(a.reshape(1), b.reshape(1), cv::NORM_INF);
    }
  }
  return testing::AssertionSuccess();
}

/// decode() == cv::imread(IMREAD_UNCHANGED), bit for bit, and nothing printed on the way.
testing::AssertionResult decodesLikeOpenCv(const std::string& path) {
  const cv::Mat expected = cv::imread(path, cv::IMREAD_UNCHANGED);
  if (expected.empty()) return testing::AssertionFailure() << "OpenCV cannot read " << path;
  testing::internal::CaptureStderr();
  std::optional<cv::Mat> got;
  std::string error;
  try {
    got = decode(path);
  } catch (const InputError& e) {
    error = e.what();
  }
  const std::string printed = testing::internal::GetCapturedStderr();
  if (!error.empty()) return testing::AssertionFailure() << error;
  if (!got) return testing::AssertionFailure() << path << ": decode() returned nullopt";
  if (!printed.empty()) return testing::AssertionFailure() << path << " printed: " << printed;
  testing::AssertionResult same = identical(*got, expected);
  if (!same) return testing::AssertionFailure() << path << ": " << same.message();
  if (cv::norm(*got, expected, cv::NORM_INF) != 0) {
    return testing::AssertionFailure() << path << ": norm of the difference is not 0";
  }
  return testing::AssertionSuccess();
}

/// The InputError decode() throws, which must name the file; "" when it throws none.
std::string decodeError(const std::string& path) {
  testing::internal::CaptureStderr();
  std::string error;
  try {
    decode(path);
  } catch (const InputError& e) {
    error = e.what();
  }
  const std::string printed = testing::internal::GetCapturedStderr();
  EXPECT_EQ(printed, "") << path;
  if (!error.empty()) {
    EXPECT_NE(error.find(path), std::string::npos) << error;
  }
  return error;
}

std::vector<unsigned char> readBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void writeBytes(const std::string& path, const std::vector<unsigned char>& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(bytes.data()),
            static_cast<std::streamsize>(bytes.size()));
}

/// A copy of `path` cut to `fraction` of its size.
std::string truncatedCopy(const std::string& path, const std::string& out, double fraction) {
  std::vector<unsigned char> bytes = readBytes(path);
  bytes.resize(static_cast<std::size_t>(static_cast<double>(bytes.size()) * fraction));
  writeBytes(out, bytes);
  return out;
}

/// A star-field-like test image: a noisy background and a few bright blobs, so that
/// every codec sees both flat areas and edges.
cv::Mat starField(int width, int height, int type, std::uint64_t seed) {
  cv::RNG rng(seed);
  const double top = CV_MAT_DEPTH(type) == CV_16U ? 65535 : CV_MAT_DEPTH(type) == CV_32F ? 1 : 255;
  cv::Mat image(height, width, type);
  rng.fill(image, cv::RNG::NORMAL, cv::Scalar::all(0.1 * top), cv::Scalar::all(0.03 * top));
  for (int i = 0; i < 12; ++i) {
    const cv::Point centre(rng.uniform(0, width), rng.uniform(0, height));
    cv::Scalar colour;
    for (int c = 0; c < 4; ++c) colour[c] = rng.uniform(0.3, 1.0) * top;
    cv::circle(image, centre, rng.uniform(1, 5), colour, cv::FILLED, cv::LINE_AA);
  }
  if (CV_MAT_CN(type) == 4) {  // some transparency, and full opacity elsewhere
    std::vector<cv::Mat> planes;
    cv::split(image, planes);
    planes[3].setTo(cv::Scalar::all(top));
    planes[3](cv::Rect(0, 0, width / 3, height / 2)).setTo(cv::Scalar::all(top / 3));
    cv::merge(planes, image);
  }
  return image;
}

class ImageCodecs : public testing::Test {
 protected:
  void SetUp() override {
    std::string templ = (fs::temp_directory_path() / "st_image_codecs_XXXXXX").string();
    ASSERT_NE(mkdtemp(templ.data()), nullptr);
    dir_ = templ;
  }
  void TearDown() override {
    std::error_code ignored;
    fs::remove_all(dir_, ignored);
  }
  std::string file(const std::string& name) const { return (fs::path(dir_) / name).string(); }

  /// cv::imwrite, checked.
  std::string written(const std::string& name, const cv::Mat& image,
                      const std::vector<int>& params = {}) const {
    const std::string path = file(name);
    EXPECT_TRUE(cv::imwrite(path, image, params)) << path;
    return path;
  }

  std::string dir_;
};

// --------------------------------------------------------------- writers for rare layouts

struct TiffSpec {
  std::uint16_t bits = 8;
  std::uint16_t photometric = PHOTOMETRIC_MINISBLACK;
  std::uint16_t sample_format = SAMPLEFORMAT_UINT;
  std::uint16_t planar = PLANARCONFIG_CONTIG;
  std::uint16_t compression = COMPRESSION_NONE;
  std::uint16_t predictor = 1;
  std::uint16_t orientation = ORIENTATION_TOPLEFT;
  std::uint16_t extra_sample = EXTRASAMPLE_UNSPECIFIED;  // for a 4th (or 2nd grey) sample
  std::uint32_t tile = 0;                                // 0: strips
  std::uint32_t rows_per_strip = 5;
  const char* mode = "w";  // "wb": big-endian, "w8": BigTIFF
};

/// Writes `samples` (file sample order, 8U for 1- and 8-bit, 16U, 32F) with libtiff, for the
/// layouts cv::imwrite never produces: tiles, palettes, bilevel, planes, orientations...
void writeTiff(const std::string& path, const cv::Mat& samples, const TiffSpec& spec) {
  TIFF* tif = TIFFOpen(path.c_str(), spec.mode);
  ASSERT_NE(tif, nullptr) << path;
  const int channels = samples.channels();
  TIFFSetField(tif, TIFFTAG_IMAGEWIDTH, static_cast<std::uint32_t>(samples.cols));
  TIFFSetField(tif, TIFFTAG_IMAGELENGTH, static_cast<std::uint32_t>(samples.rows));
  TIFFSetField(tif, TIFFTAG_BITSPERSAMPLE, spec.bits);
  TIFFSetField(tif, TIFFTAG_SAMPLESPERPIXEL, static_cast<std::uint16_t>(channels));
  TIFFSetField(tif, TIFFTAG_PHOTOMETRIC, spec.photometric);
  TIFFSetField(tif, TIFFTAG_SAMPLEFORMAT, spec.sample_format);
  TIFFSetField(tif, TIFFTAG_PLANARCONFIG, spec.planar);
  TIFFSetField(tif, TIFFTAG_COMPRESSION, spec.compression);
  TIFFSetField(tif, TIFFTAG_ORIENTATION, spec.orientation);
  if (spec.predictor != 1) TIFFSetField(tif, TIFFTAG_PREDICTOR, spec.predictor);
  const bool colour = spec.photometric == PHOTOMETRIC_RGB;
  if ((colour && channels == 4) || (!colour && channels == 2)) {
    std::uint16_t extra = spec.extra_sample;
    TIFFSetField(tif, TIFFTAG_EXTRASAMPLES, 1, &extra);
  }
  if (spec.photometric == PHOTOMETRIC_PALETTE) {
    const std::size_t n = std::size_t{1} << spec.bits;
    std::vector<std::uint16_t> red(n), green(n), blue(n);
    for (std::size_t i = 0; i < n; ++i) {
      red[i] = static_cast<std::uint16_t>(i * 257);
      green[i] = static_cast<std::uint16_t>((n - 1 - i) * 257);
      blue[i] = static_cast<std::uint16_t>((i * 7 % n) * 257);
    }
    TIFFSetField(tif, TIFFTAG_COLORMAP, red.data(), green.data(), blue.data());
  }
  if (spec.compression == COMPRESSION_SGILOG) {  // LogLuv from float XYZ samples
    TIFFSetField(tif, TIFFTAG_SGILOGDATAFMT, SGILOGDATAFMT_FLOAT);
  }
  if (spec.compression == COMPRESSION_JPEG) {  // libtiff converts our RGB rows to YCbCr
    TIFFSetField(tif, TIFFTAG_JPEGQUALITY, 90);
    TIFFSetField(tif, TIFFTAG_JPEGCOLORMODE, JPEGCOLORMODE_RGB);
  }
  // Rows as stored: bilevel packs 8 pixels a byte, high bit first.
  const std::size_t sample_bytes = spec.bits == 1 ? 1 : spec.bits / 8;
  auto packedRow = [&](int y, int plane) {
    std::vector<unsigned char> row;
    const unsigned char* src = samples.ptr(y);
    const int per_pixel = plane < 0 ? channels : 1;
    const int offset = plane < 0 ? 0 : plane;
    if (spec.bits == 1) {
      row.assign((samples.cols + 7) / 8, 0);
      for (int x = 0; x < samples.cols; ++x)
        if (src[x]) row[x / 8] |= static_cast<unsigned char>(0x80 >> (x % 8));
      return row;
    }
    for (int x = 0; x < samples.cols; ++x)
      for (int c = 0; c < per_pixel; ++c) {
        const unsigned char* s = src + ((x * channels) + offset + c) * sample_bytes;
        row.insert(row.end(), s, s + sample_bytes);
      }
    return row;
  };
  if (spec.tile != 0) {
    TIFFSetField(tif, TIFFTAG_TILEWIDTH, spec.tile);
    TIFFSetField(tif, TIFFTAG_TILELENGTH, spec.tile);
    const std::size_t tile_row = spec.tile * channels * sample_bytes;
    for (std::uint32_t y0 = 0; y0 < static_cast<std::uint32_t>(samples.rows); y0 += spec.tile)
      for (std::uint32_t x0 = 0; x0 < static_cast<std::uint32_t>(samples.cols); x0 += spec.tile) {
        std::vector<unsigned char> tile(tile_row * spec.tile, 0);
        for (std::uint32_t i = 0;
             i < spec.tile && y0 + i < static_cast<std::uint32_t>(samples.rows); ++i) {
          const std::vector<unsigned char> row = packedRow(static_cast<int>(y0 + i), -1);
          const std::size_t begin = x0 * channels * sample_bytes;
          const std::size_t n = std::min(tile_row, row.size() - begin);
          std::memcpy(tile.data() + i * tile_row, row.data() + begin, n);
        }
        ASSERT_GE(TIFFWriteTile(tif, tile.data(), x0, y0, 0, 0), 0);
      }
  } else {
    TIFFSetField(tif, TIFFTAG_ROWSPERSTRIP, spec.rows_per_strip);
    const int planes = spec.planar == PLANARCONFIG_SEPARATE ? channels : 1;
    for (int p = 0; p < planes; ++p)
      for (int y = 0; y < samples.rows; ++y) {
        std::vector<unsigned char> row = packedRow(y, planes > 1 ? p : -1);
        ASSERT_EQ(TIFFWriteScanline(tif, row.data(), static_cast<std::uint32_t>(y),
                                    static_cast<std::uint16_t>(p)),
                  1);
      }
  }
  TIFFClose(tif);
}

struct PngSpec {
  int color_type = PNG_COLOR_TYPE_GRAY;
  int bit_depth = 8;
  bool trns = false;
  bool interlaced = false;
};

/// Writes `samples` (file order: grey, grey+alpha, RGB, RGBA or palette indices; 8U or 16U)
/// with libpng, for layouts cv::imwrite never produces.
void writePngWithLibpng(const std::string& path, const cv::Mat& samples, const PngSpec& spec) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  ASSERT_NE(f, nullptr);
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png_create_info_struct(png);
  png_init_io(png, f);
  png_set_IHDR(png, info, samples.cols, samples.rows, spec.bit_depth, spec.color_type,
               spec.interlaced ? PNG_INTERLACE_ADAM7 : PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  if (spec.color_type == PNG_COLOR_TYPE_PALETTE) {
    std::vector<png_color> palette(16);
    for (int i = 0; i < 16; ++i)
      palette[i] = {static_cast<png_byte>(i * 17), static_cast<png_byte>(255 - i * 13),
                    static_cast<png_byte>(i * 5)};
    png_set_PLTE(png, info, palette.data(), 16);
    if (spec.trns) {
      png_byte alpha[4] = {0, 64, 128, 200};
      png_set_tRNS(png, info, alpha, 4, nullptr);
    }
  } else if (spec.trns) {
    png_color_16 key{};
    key.gray = 3;
    key.red = 30;
    key.green = 40;
    key.blue = 50;
    png_set_tRNS(png, info, nullptr, 0, &key);
  }
  png_write_info(png, info);
  if (spec.bit_depth < 8) png_set_packing(png);
  if (spec.bit_depth == 16) png_set_swap(png);  // the test machine is little-endian
  std::vector<png_bytep> rows(samples.rows);
  for (int y = 0; y < samples.rows; ++y) rows[y] = const_cast<png_bytep>(samples.ptr(y));
  png_write_image(png, rows.data());
  png_write_end(png, info);
  png_destroy_write_struct(&png, &info);
  std::fclose(f);
}

/// A 4-component (Adobe CMYK) JPEG, which cv::imwrite cannot make.
void writeCmykJpeg(const std::string& path, const cv::Mat& cmyk) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  ASSERT_NE(f, nullptr);
  jpeg_compress_struct cinfo{};
  jpeg_error_mgr err{};
  cinfo.err = jpeg_std_error(&err);
  jpeg_create_compress(&cinfo);
  jpeg_stdio_dest(&cinfo, f);
  cinfo.image_width = cmyk.cols;
  cinfo.image_height = cmyk.rows;
  cinfo.input_components = 4;
  cinfo.in_color_space = JCS_CMYK;
  jpeg_set_defaults(&cinfo);
  jpeg_set_quality(&cinfo, 90, TRUE);
  jpeg_start_compress(&cinfo, TRUE);
  for (int y = 0; y < cmyk.rows; ++y) {
    JSAMPROW row = const_cast<JSAMPROW>(cmyk.ptr(y));
    jpeg_write_scanlines(&cinfo, &row, 1);
  }
  jpeg_finish_compress(&cinfo);
  jpeg_destroy_compress(&cinfo);
  std::fclose(f);
}

// ----------------------------------------------------------------------------- real data

std::vector<std::string> realImages() {
  std::vector<std::string> out;
  auto add = [&](const fs::path& dir, bool recursive, std::size_t limit) {
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) return;
    std::vector<std::string> found;
    auto take = [&](const fs::directory_entry& e) {
      const std::string ext = e.path().extension().string();
      if (e.is_regular_file() &&
          (ext == ".png" || ext == ".jpg" || ext == ".jpeg" || ext == ".tif" || ext == ".tiff"))
        found.push_back(e.path().string());
    };
    if (recursive) {
      for (const auto& e : fs::recursive_directory_iterator(dir, ec)) take(e);
    } else {
      for (const auto& e : fs::directory_iterator(dir, ec)) take(e);
    }
    std::sort(found.begin(), found.end());
    if (found.size() > limit) found.resize(limit);
    out.insert(out.end(), found.begin(), found.end());
  };
  add(fs::path(ST_REPO_DIR) / "tests/data/tetra3", false, 1000);
  const char* shared = std::getenv("ST_SHARED_DATA_DIR");  // the override tests/support honours
  add(fs::path(shared != nullptr ? shared : ST_SHARED_DATA_DIR) / "images", true, 1000);
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(fs::path(ST_REPO_DIR) / "rawlogs", ec)) {
    const std::string name = e.path().filename().string();
    if (e.is_directory() && name.size() > 7 && name.compare(name.size() - 7, 7, "_Images") == 0)
      add(e.path(), false, 3);
  }
  return out;
}

TEST(ImageCodecsRealData, EveryRealFrameDecodesLikeOpenCv) {
  const std::vector<std::string> images = realImages();
  if (images.empty()) GTEST_SKIP() << "no real images found";
  for (const std::string& path : images) {
    EXPECT_TRUE(decodesLikeOpenCv(path));
  }
  std::cout << "[ INFO     ] " << images.size() << " real images compared" << std::endl;
}

TEST(ImageCodecsRealData, SniffsByContentNotName) {
  const std::string tiff =
      std::string(ST_REPO_DIR) + "/tests/data/tetra3/2019-07-29T204726_Alt40_Azi-135_Try1.tiff";
  if (!fs::exists(tiff)) GTEST_SKIP() << tiff << " missing";
  EXPECT_EQ(sniffFormat(tiff), Format::kTiff);
}

// -------------------------------------------------------------- synthetic, via cv::imwrite

TEST_F(ImageCodecs, PngFromImwrite) {
  int i = 0;
  for (const int type : {CV_8UC1, CV_16UC1, CV_8UC3, CV_8UC4, CV_16UC3, CV_16UC4}) {
    ++i;
    const std::string path =
        written("imwrite" + std::to_string(i) + ".png", starField(97, 61, type, 100 + i));
    EXPECT_EQ(sniffFormat(path), Format::kPng);
    EXPECT_TRUE(decodesLikeOpenCv(path)) << cv::typeToString(type);
  }
}

TEST_F(ImageCodecs, JpegFromImwrite) {
  const std::vector<int> q90 = {cv::IMWRITE_JPEG_QUALITY, 90};
  const std::vector<int> progressive = {cv::IMWRITE_JPEG_QUALITY, 90, cv::IMWRITE_JPEG_PROGRESSIVE,
                                        1};
  const std::vector<std::string> paths = {
      written("grey.jpg", starField(97, 61, CV_8UC1, 1), q90),
      written("colour.jpg", starField(97, 61, CV_8UC3, 2), q90),
      written("colour_big.jpg", starField(640, 480, CV_8UC3, 3), q90),
      written("grey_progressive.jpg", starField(97, 61, CV_8UC1, 4), progressive),
      written("colour_progressive.jpg", starField(333, 222, CV_8UC3, 5), progressive),
      written("colour_q100.jpg", starField(64, 48, CV_8UC3, 6), {cv::IMWRITE_JPEG_QUALITY, 100}),
  };
  for (const std::string& path : paths) {
    EXPECT_EQ(sniffFormat(path), Format::kJpeg);
    EXPECT_TRUE(decodesLikeOpenCv(path));
  }
}

TEST_F(ImageCodecs, CmykJpeg) {
  const std::string path = file("cmyk.jpg");
  writeCmykJpeg(path, starField(75, 41, CV_8UC4, 7));
  EXPECT_TRUE(decodesLikeOpenCv(path));
}

TEST_F(ImageCodecs, TiffFromImwrite) {
  int i = 0;
  for (const int type : {CV_8UC1, CV_16UC1, CV_8UC3, CV_16UC3, CV_8UC4, CV_16UC4, CV_32FC1}) {
    for (const int compression : {1 /* none */, 5 /* LZW */}) {
      ++i;
      const std::string path =
          written("imwrite" + std::to_string(i) + ".tiff", starField(97, 61, type, 200 + i),
                  {cv::IMWRITE_TIFF_COMPRESSION, compression});
      EXPECT_EQ(sniffFormat(path), Format::kTiff);
      EXPECT_TRUE(decodesLikeOpenCv(path)) << cv::typeToString(type) << " " << compression;
    }
  }
}

TEST_F(ImageCodecs, PnmFromImwrite) {
  const std::vector<std::string> paths = {
      written("grey8.pgm", starField(97, 61, CV_8UC1, 11)),
      written("grey16.pgm", starField(97, 61, CV_16UC1, 12)),
      written("colour8.ppm", starField(97, 61, CV_8UC3, 13)),
      written("colour16.ppm", starField(97, 61, CV_16UC3, 14)),
  };
  for (const std::string& path : paths) {
    EXPECT_EQ(sniffFormat(path), Format::kPnm);
    EXPECT_TRUE(decodesLikeOpenCv(path));
  }
}

// --------------------------------------------------------- synthetic, rarer layouts by hand

TEST_F(ImageCodecs, PnmHeadersWithCommentsAndOddMaxval) {
  auto pnm = [&](const std::string& name, const std::string& header, const cv::Mat& body) {
    std::vector<unsigned char> bytes(header.begin(), header.end());
    for (int y = 0; y < body.rows; ++y)
      bytes.insert(bytes.end(), body.ptr(y), body.ptr(y) + body.cols * body.elemSize());
    writeBytes(file(name), bytes);
    return file(name);
  };
  cv::Mat grey = starField(13, 7, CV_8UC1, 21);
  cv::Mat wide(7, 13, CV_16UC1);
  cv::randu(wide, 0, 1000);
  cv::Mat wide_be;  // big-endian in the file
  wide.copyTo(wide_be);
  for (int y = 0; y < 7; ++y)
    for (int x = 0; x < 13; ++x) {
      const std::uint16_t v = wide.at<std::uint16_t>(y, x);
      wide_be.at<std::uint16_t>(y, x) = static_cast<std::uint16_t>((v >> 8) | (v << 8));
    }
  const std::vector<std::string> paths = {
      pnm("comments.pgm", "P5\n# a comment\n13 # width\n7\n#maxval next\n255\n", grey),
      pnm("maxval100.pgm", "P5 13 7 100\n", grey),  // kept raw, not rescaled, as OpenCV
      pnm("maxval1000.pgm", "P5\r\n13\t7 1000\n", wide_be),
      pnm("colour.ppm", "P6 # rgb\n4 7\n255\n", starField(4, 7, CV_8UC3, 22)),
  };
  for (const std::string& path : paths) EXPECT_TRUE(decodesLikeOpenCv(path));
}

TEST_F(ImageCodecs, PngLayoutsImwriteNeverMakes) {
  cv::Mat indices(31, 23, CV_8UC1);
  cv::randu(indices, 0, 16);
  cv::Mat grey4(31, 23, CV_8UC1);
  cv::randu(grey4, 0, 16);
  struct Case {
    std::string name;
    cv::Mat samples;
    PngSpec spec;
  };
  const std::vector<Case> cases = {
      {"palette.png", indices, {PNG_COLOR_TYPE_PALETTE, 8, false, false}},
      {"palette_trns.png", indices, {PNG_COLOR_TYPE_PALETTE, 8, true, false}},
      {"palette4.png", indices, {PNG_COLOR_TYPE_PALETTE, 4, false, false}},
      {"grey4.png", grey4, {PNG_COLOR_TYPE_GRAY, 4, false, false}},
      {"grey_trns.png", starField(23, 31, CV_8UC1, 31), {PNG_COLOR_TYPE_GRAY, 8, true, false}},
      {"grey_alpha.png",
       starField(23, 31, CV_8UC2, 32),
       {PNG_COLOR_TYPE_GRAY_ALPHA, 8, false, false}},
      {"grey_alpha16.png",
       starField(23, 31, CV_16UC2, 33),
       {PNG_COLOR_TYPE_GRAY_ALPHA, 16, false, false}},
      {"rgb_trns.png", starField(23, 31, CV_8UC3, 34), {PNG_COLOR_TYPE_RGB, 8, true, false}},
      {"rgb16_trns.png", starField(23, 31, CV_16UC3, 35), {PNG_COLOR_TYPE_RGB, 16, true, false}},
      {"interlaced.png", starField(23, 31, CV_8UC3, 36), {PNG_COLOR_TYPE_RGB, 8, false, true}},
      {"interlaced16.png", starField(23, 31, CV_16UC1, 37), {PNG_COLOR_TYPE_GRAY, 16, false, true}},
  };
  for (const Case& c : cases) {
    writePngWithLibpng(file(c.name), c.samples, c.spec);
    EXPECT_TRUE(decodesLikeOpenCv(file(c.name)));
  }
}

TEST_F(ImageCodecs, TiffLayoutsImwriteNeverMakes) {
  cv::Mat bilevel(29, 37, CV_8UC1);
  cv::randu(bilevel, 0, 2);
  struct Case {
    std::string name;
    cv::Mat samples;
    TiffSpec spec;
  };
  TiffSpec tiled8;
  tiled8.tile = 16;
  TiffSpec tiled16_rgb;
  tiled16_rgb.bits = 16;
  tiled16_rgb.photometric = PHOTOMETRIC_RGB;
  tiled16_rgb.tile = 16;
  tiled16_rgb.compression = COMPRESSION_ADOBE_DEFLATE;
  TiffSpec tiled16_grey = tiled16_rgb;
  tiled16_grey.photometric = PHOTOMETRIC_MINISBLACK;
  TiffSpec tiled_rgb8 = tiled8;
  tiled_rgb8.photometric = PHOTOMETRIC_RGB;
  TiffSpec tiled_float;
  tiled_float.bits = 32;
  tiled_float.sample_format = SAMPLEFORMAT_IEEEFP;
  tiled_float.tile = 16;
  TiffSpec float_predictor;
  float_predictor.bits = 32;
  float_predictor.sample_format = SAMPLEFORMAT_IEEEFP;
  float_predictor.compression = COMPRESSION_ADOBE_DEFLATE;
  float_predictor.predictor = 3;
  TiffSpec grey16_big_endian;
  grey16_big_endian.bits = 16;
  grey16_big_endian.mode = "wb";
  grey16_big_endian.compression = COMPRESSION_LZW;
  grey16_big_endian.predictor = 2;
  TiffSpec rgba16_assoc;
  rgba16_assoc.bits = 16;
  rgba16_assoc.photometric = PHOTOMETRIC_RGB;
  rgba16_assoc.extra_sample = EXTRASAMPLE_ASSOCALPHA;
  TiffSpec rgba8_unassoc;
  rgba8_unassoc.photometric = PHOTOMETRIC_RGB;
  rgba8_unassoc.extra_sample = EXTRASAMPLE_UNASSALPHA;
  TiffSpec rgba8_assoc = rgba8_unassoc;
  rgba8_assoc.extra_sample = EXTRASAMPLE_ASSOCALPHA;
  TiffSpec palette;
  palette.photometric = PHOTOMETRIC_PALETTE;
  TiffSpec min_is_white;
  min_is_white.photometric = PHOTOMETRIC_MINISWHITE;
  TiffSpec bilevel_spec;
  bilevel_spec.bits = 1;
  bilevel_spec.compression = COMPRESSION_CCITTFAX4;
  TiffSpec planar8;
  planar8.photometric = PHOTOMETRIC_RGB;
  planar8.planar = PLANARCONFIG_SEPARATE;
  TiffSpec grey_alpha8;
  grey_alpha8.extra_sample = EXTRASAMPLE_UNASSALPHA;
  TiffSpec grey_alpha16 = grey_alpha8;  // OpenCV reads it as 8-bit grey through RGBA
  grey_alpha16.bits = 16;
  TiffSpec big_tiff;
  big_tiff.bits = 16;
  big_tiff.mode = "w8";
  TiffSpec jpeg_ycbcr;
  jpeg_ycbcr.photometric = PHOTOMETRIC_YCBCR;
  jpeg_ycbcr.compression = COMPRESSION_JPEG;
  jpeg_ycbcr.rows_per_strip = 16;

  const std::vector<Case> cases = {
      {"tiled8.tiff", starField(37, 29, CV_8UC1, 41), tiled8},
      {"tiled_rgb8.tiff", starField(37, 29, CV_8UC3, 42), tiled_rgb8},
      {"tiled16_rgb.tiff", starField(37, 29, CV_16UC3, 43), tiled16_rgb},
      {"tiled16_grey.tiff", starField(37, 29, CV_16UC1, 44), tiled16_grey},
      {"tiled_float.tiff", starField(37, 29, CV_32FC1, 45), tiled_float},
      {"float_predictor.tiff", starField(37, 29, CV_32FC1, 46), float_predictor},
      {"grey16_big_endian.tiff", starField(37, 29, CV_16UC1, 47), grey16_big_endian},
      {"rgba16_assoc.tiff", starField(37, 29, CV_16UC4, 48), rgba16_assoc},
      {"rgba8_unassoc.tiff", starField(37, 29, CV_8UC4, 49), rgba8_unassoc},
      {"rgba8_assoc.tiff", starField(37, 29, CV_8UC4, 50), rgba8_assoc},
      {"palette.tiff", starField(37, 29, CV_8UC1, 51), palette},
      {"min_is_white.tiff", starField(37, 29, CV_8UC1, 52), min_is_white},
      {"bilevel.tiff", bilevel, bilevel_spec},
      {"planar8.tiff", starField(37, 29, CV_8UC3, 53), planar8},
      {"grey_alpha8.tiff", starField(37, 29, CV_8UC2, 54), grey_alpha8},
      {"grey_alpha16.tiff", starField(37, 29, CV_16UC2, 57), grey_alpha16},
      {"big.tiff", starField(37, 29, CV_16UC1, 55), big_tiff},
      {"jpeg_ycbcr.tiff", starField(64, 48, CV_8UC3, 56), jpeg_ycbcr},
  };
  for (const Case& c : cases) {
    writeTiff(file(c.name), c.samples, c.spec);
    EXPECT_TRUE(decodesLikeOpenCv(file(c.name)));
  }
}

/// Layouts whose OpenCV result is not a faithful image (16-bit min-is-white comes back as a
/// negative, 16-bit separate planes as noise), or that this reader does not reproduce (signed
/// samples, orientations other than top-left, float colour, LogLuv): an InputError naming the file
/// and the layout, never a guess.
TEST_F(ImageCodecs, UnsupportedTiffLayoutsAreInputErrors) {
  TiffSpec white16;
  white16.bits = 16;
  white16.photometric = PHOTOMETRIC_MINISWHITE;
  TiffSpec planar16;
  planar16.bits = 16;
  planar16.photometric = PHOTOMETRIC_RGB;
  planar16.planar = PLANARCONFIG_SEPARATE;
  TiffSpec signed16;
  signed16.bits = 16;
  signed16.sample_format = SAMPLEFORMAT_INT;
  TiffSpec bottom_left16;
  bottom_left16.bits = 16;
  bottom_left16.orientation = ORIENTATION_BOTLEFT;
  TiffSpec bottom_left8;
  bottom_left8.orientation = ORIENTATION_BOTLEFT;
  TiffSpec log_luv;
  log_luv.bits = 32;
  log_luv.sample_format = SAMPLEFORMAT_IEEEFP;
  log_luv.photometric = PHOTOMETRIC_LOGLUV;
  log_luv.compression = COMPRESSION_SGILOG;
  TiffSpec float_rgb;
  float_rgb.bits = 32;
  float_rgb.sample_format = SAMPLEFORMAT_IEEEFP;
  float_rgb.photometric = PHOTOMETRIC_RGB;
  struct Case {
    std::string name;
    cv::Mat samples;
    TiffSpec spec;
  };
  const std::vector<Case> cases = {
      {"white16.tiff", starField(37, 29, CV_16UC1, 61), white16},
      {"planar16.tiff", starField(37, 29, CV_16UC3, 62), planar16},
      {"signed16.tiff", starField(37, 29, CV_16UC1, 63), signed16},
      {"bottom_left16.tiff", starField(37, 29, CV_16UC1, 64), bottom_left16},
      {"bottom_left8.tiff", starField(37, 29, CV_8UC1, 66), bottom_left8},
      {"float_rgb.tiff", starField(37, 29, CV_32FC3, 65), float_rgb},
      {"log_luv.tiff", starField(37, 29, CV_32FC3, 67), log_luv},
  };
  for (const Case& c : cases) {
    writeTiff(file(c.name), c.samples, c.spec);
    const std::string error = decodeError(file(c.name));
    EXPECT_NE(error.find("unsupported TIFF layout"), std::string::npos) << c.name << ": " << error;
  }
}

// ----------------------------------------------------------------------------- writePng

TEST_F(ImageCodecs, WritePngRoundTripsAndMatchesImwrite) {
  int i = 0;
  for (const int type : {CV_8UC1, CV_16UC1, CV_8UC3, CV_16UC3, CV_8UC4, CV_16UC4}) {
    const cv::Mat image = starField(97, 61, type, 300 + i);
    const std::string ours = file("ours" + std::to_string(i) + ".png");
    const std::string theirs = written("theirs" + std::to_string(i) + ".png", image);
    ++i;
    writePng(ours, image);
    const std::optional<cv::Mat> back = decode(ours);
    ASSERT_TRUE(back);
    EXPECT_TRUE(identical(*back, image)) << cv::typeToString(type);
    EXPECT_TRUE(identical(cv::imread(ours, cv::IMREAD_UNCHANGED), image));
    EXPECT_EQ(readBytes(ours), readBytes(theirs)) << "not the bytes cv::imwrite writes";
  }
  // A view into a larger image (rows not contiguous) writes just the view.
  const cv::Mat big = starField(120, 80, CV_16UC1, 399);
  const cv::Mat view = big(cv::Rect(10, 5, 50, 40));
  writePng(file("view.png"), view);
  EXPECT_TRUE(identical(*decode(file("view.png")), view));
}

TEST_F(ImageCodecs, WritePngRefusesWhatPngCannotHold) {
  for (const cv::Mat& bad :
       {cv::Mat(4, 4, CV_32FC1, cv::Scalar(0)), cv::Mat(4, 4, CV_8UC2, cv::Scalar(0)), cv::Mat()}) {
    const std::string path = file("bad.png");
    try {
      writePng(path, bad);
      ADD_FAILURE() << "no InputError for " << cv::typeToString(bad.type());
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    }
  }
  const std::string nowhere = file("no/such/dir/x.png");
  try {
    writePng(nowhere, cv::Mat(4, 4, CV_8UC1, cv::Scalar(0)));
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(nowhere), std::string::npos) << e.what();
  }
}

// ------------------------------------------------------------------------ damaged files

TEST_F(ImageCodecs, HalfFilesAreInputErrorsNamingTheFile) {
  const std::vector<std::string> whole = {
      written("half.jpg", starField(320, 240, CV_8UC3, 71), {cv::IMWRITE_JPEG_QUALITY, 90}),
      written("half_progressive.jpg", starField(320, 240, CV_8UC1, 72),
              {cv::IMWRITE_JPEG_PROGRESSIVE, 1}),
      written("half.png", starField(320, 240, CV_16UC1, 73)),
      written("half_lzw.tiff", starField(320, 240, CV_16UC1, 74)),
      written("half.pgm", starField(320, 240, CV_16UC1, 75)),
  };
  std::vector<std::string> cut;
  for (const std::string& path : whole) {
    cut.push_back(truncatedCopy(path, file("cut_" + fs::path(path).filename().string()), 0.5));
  }
  // A TIFF whose directory comes before the pixels (as in tests/data/tetra3): the header
  // reads, the strips run out.
  const std::string tetra3 =
      std::string(ST_REPO_DIR) + "/tests/data/tetra3/2019-07-29T204726_Alt40_Azi-135_Try1.tiff";
  if (fs::exists(tetra3)) cut.push_back(truncatedCopy(tetra3, file("cut_tetra3.tiff"), 0.5));
  for (const std::string& path : cut) {
    const std::string error = decodeError(path);
    EXPECT_NE(error, "") << path << " decoded although cut in half";
  }
  if (fs::exists(tetra3)) {
    const std::string error = decodeError(file("cut_tetra3.tiff"));
    EXPECT_NE(error.find("of 768 rows decoded"), std::string::npos) << error;
  }
  EXPECT_NE(decodeError(file("cut_half.jpg")).find("truncated"), std::string::npos);
  EXPECT_NE(decodeError(file("cut_half.png")).find("truncated"), std::string::npos);
  EXPECT_NE(decodeError(file("cut_half.pgm")).find("truncated"), std::string::npos);
}

TEST_F(ImageCodecs, CorruptPixelDataIsAnInputError) {
  // Pixel data in the middle of each file: a PNG's IDAT, an LZW TIFF's strips (cv::imwrite
  // puts the directory at the end).
  for (const std::string& path : {written("corrupt.png", starField(64, 64, CV_8UC1, 81)),
                                  written("corrupt8.tiff", starField(64, 64, CV_8UC3, 82)),
                                  written("corrupt16.tiff", starField(64, 64, CV_16UC1, 83))}) {
    std::vector<unsigned char> bytes = readBytes(path);
    for (std::size_t i = bytes.size() / 3; i < bytes.size() / 3 + 32; ++i) bytes[i] = 0xff;
    writeBytes(path, bytes);
    EXPECT_NE(decodeError(path), "") << path;
  }
}

TEST_F(ImageCodecs, PngWithoutItsEndChunkIsAnInputError) {
  const std::string png = written("no_iend.png", starField(64, 64, CV_8UC1, 84));
  std::vector<unsigned char> bytes = readBytes(png);
  bytes.resize(bytes.size() - 12);  // IEND: length, type, CRC
  writeBytes(png, bytes);
  EXPECT_NE(decodeError(png).find("truncated"), std::string::npos);
}

/// Damage anywhere -- header, tables, pixel data, a cut -- is either still a decodable file
/// or an InputError naming it: no crash, no other exception, nothing on stderr.
TEST_F(ImageCodecs, RandomlyDamagedFilesNeverCrash) {
  TiffSpec tiled;
  tiled.tile = 16;
  tiled.compression = COMPRESSION_LZW;
  writeTiff(file("seed_tiled.tiff"), starField(37, 29, CV_8UC1, 91), tiled);
  const std::vector<std::string> seeds = {
      written("seed8.png", starField(40, 30, CV_8UC1, 92)),
      written("seed16.png", starField(40, 30, CV_16UC3, 93)),
      written("seed.jpg", starField(40, 30, CV_8UC3, 94)),
      written("seed_progressive.jpg", starField(40, 30, CV_8UC1, 95),
              {cv::IMWRITE_JPEG_PROGRESSIVE, 1}),
      written("seed16.tiff", starField(40, 30, CV_16UC1, 96)),
      written("seed8.tiff", starField(40, 30, CV_8UC3, 97), {cv::IMWRITE_TIFF_COMPRESSION, 1}),
      written("seed16.pgm", starField(40, 30, CV_16UC1, 98)),
      file("seed_tiled.tiff"),
  };
  cv::RNG rng(20240601);
  int errors = 0;
  int decoded = 0;
  for (const std::string& seed : seeds) {
    const std::vector<unsigned char> original = readBytes(seed);
    const std::string damaged = file("damaged" + fs::path(seed).extension().string());
    for (int k = 0; k < 150; ++k) {
      std::vector<unsigned char> bytes = original;
      if (k % 5 == 0) {
        bytes.resize(static_cast<std::size_t>(rng.uniform(8, static_cast<int>(bytes.size()))));
      } else {
        const int flips = rng.uniform(1, 9);
        for (int f = 0; f < flips; ++f) {
          // Past the magic number, so that the same decoder is exercised.
          const int at = rng.uniform(8, static_cast<int>(bytes.size()));
          bytes[static_cast<std::size_t>(at)] = static_cast<unsigned char>(rng.uniform(0, 256));
        }
      }
      writeBytes(damaged, bytes);
      (decodeError(damaged).empty() ? decoded : errors)++;
    }
  }
  EXPECT_GT(errors, 0);
  std::cout << "[ INFO     ] damaged files: " << errors << " InputErrors, " << decoded
            << " still decodable" << std::endl;
}

TEST_F(ImageCodecs, HeaderClaimingHugeImageIsRefusedBeforeAllocating) {
  writeBytes(file("huge.pgm"), {'P', '5', ' ', '9', '9', '9', '9', '9',  ' ', '9', '9',
                                '9', '9', '9', ' ', '2', '5', '5', '\n', 0,   0});
  EXPECT_NE(decodeError(file("huge.pgm")).find("too large"), std::string::npos);
  writeBytes(file("empty.pgm"), {'P', '5', ' ', '0', ' ', '5', ' ', '2', '5', '5', '\n'});
  EXPECT_NE(decodeError(file("empty.pgm")).find("no pixels"), std::string::npos);
}

TEST_F(ImageCodecs, RandomBytesAreOtherAndMissingFilesAreInputErrors) {
  cv::Mat noise(1, 4096, CV_8UC1);
  cv::randu(noise, 0, 256);
  noise.at<unsigned char>(0, 0) = 0;  // no magic number can start with it
  writeBytes(file("noise.bin"),
             std::vector<unsigned char>(noise.begin<unsigned char>(), noise.end<unsigned char>()));
  EXPECT_EQ(sniffFormat(file("noise.bin")), Format::kOther);
  EXPECT_FALSE(decode(file("noise.bin")).has_value());

  writeBytes(file("ascii.pgm"), {'P', '2', ' ', '1', ' ', '1', ' ', '9', '\n', '5', '\n'});
  EXPECT_EQ(sniffFormat(file("ascii.pgm")), Format::kOther);  // ASCII PNM: another reader's

  writeBytes(file("tiny"), {0x89, 'P'});
  EXPECT_EQ(sniffFormat(file("tiny")), Format::kOther);

  const std::string missing = file("missing.png");
  try {
    sniffFormat(missing);
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(missing), std::string::npos) << e.what();
  }
  EXPECT_NE(decodeError(missing), "");
}

}  // namespace
}  // namespace st::imageio

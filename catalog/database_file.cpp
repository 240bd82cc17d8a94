// The database file: one little-endian binary blob
//   magic "STARDB\r\n" | uint32 format version | uint32 byte-order mark 0x01020304 |
//   build parameters | build report (incl. catalog name and epoch; format 2 adds the catalog
//   path, its depth and the requested magnitude limit) | stars | pairs |
//   neighbour table | (format 3) screen stars | uint32 CRC-32 (zlib) of every byte before it.
// Format 4 adds each star's B-V (float32) after its V.
// Pair and neighbour indices are stored as uint16 when there are < 65536 stars (that keeps a
// 15 deg / V 6.5 database under 10 MB). The pair k-vector and the cone index are not stored:
// they are rebuilt from the stored, sorted values in one O(n) pass at load (a few ms), so
// they can never disagree with the data.
#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

#include <cstring>
#include <fstream>
#include <limits>
#include <type_traits>

#include <string_view>

#include "common/output_file.hpp"
#include "catalog/star_database.hpp"
#include "common/errors.hpp"

namespace st {
namespace {

constexpr char kMagic[8] = {'S', 'T', 'A', 'R', 'D', 'B', '\r', '\n'};
// 2: the report records the catalog file, its depth and the requested limit (issue 21).
// 3: the blend screen's stars (ScreenStar) after the neighbour table.
// Format 1 and 2 files still load, without what came later.
constexpr uint32_t kFormatVersion = StarDatabase::kFileFormat;  // 4: B-V per star
constexpr uint32_t kOldestReadableVersion = 1;
constexpr uint32_t kByteOrderMark = 0x01020304;

class Writer {
 public:
  template <class T>
  void put(const T& v) {
    static_assert(std::is_trivially_copyable<T>::value, "POD only");
    const char* p = reinterpret_cast<const char*>(&v);
    buf.append(p, sizeof(T));
  }
  void putString(const std::string& s) {
    put(uint32_t(s.size()));
    buf.append(s);
  }
  std::string buf;
};

class Reader {
 public:
  Reader(const std::string& path, std::string_view bytes, std::size_t end)
      : path_(path), bytes_(bytes), end_(end) {}
  template <class T>
  T get(const char* what) {
    T v;
    need(sizeof(T), what);
    std::memcpy(&v, bytes_.data() + pos_, sizeof(T));
    pos_ += sizeof(T);
    return v;
  }
  std::string getString(const char* what) {
    const uint32_t n = get<uint32_t>(what);
    need(n, what);
    std::string s(bytes_.substr(pos_, n));
    pos_ += n;
    return s;
  }
  void need(std::size_t n, const char* what) const {
    if (n > end_ - pos_)
      throw InputError(path_ + ": star database truncated or corrupt while reading " + what +
                       " at byte " + std::to_string(pos_));
  }
  std::size_t pos() const { return pos_; }
  /// Checks and skips `n` bytes, returning where they start (for bulk decoding).
  const char* raw(std::size_t n, const char* what) {
    need(n, what);
    const char* p = bytes_.data() + pos_;
    pos_ += n;
    return p;
  }

 private:
  const std::string& path_;
  std::string_view bytes_;
  std::size_t end_, pos_ = 0;
};

uint32_t crc32Of(const char* p, std::size_t n) {
  uLong crc = crc32(0L, Z_NULL, 0);
  while (n > 0) {  // zlib takes uInt lengths
    const uInt chunk = uInt(std::min<std::size_t>(n, 1u << 30));
    crc = crc32(crc, reinterpret_cast<const Bytef*>(p), chunk);
    p += chunk;
    n -= chunk;
  }
  return uint32_t(crc);
}

}  // namespace

void StarDatabase::save(const std::string& path, uint32_t format) const {
  if (format < 2 || format > kFormatVersion)
    throw InputError(path + ": star database format " + std::to_string(format) +
                     " cannot be written (2 to " + std::to_string(kFormatVersion) + ")");
  Writer w;
  w.buf.append(kMagic, sizeof kMagic);
  w.put(format);
  w.put(kByteOrderMark);
  const DatabaseParams& p = params_;
  w.put(p.max_pair_angle);
  w.put(p.mag_limit);
  w.put(p.epoch_jyear);
  w.put(uint8_t(p.aberration));
  w.put(uint8_t(p.parallax));
  w.put(p.double_star_sep);
  w.put(int32_t(p.max_stars_per_region));
  w.put(p.region_radius);
  w.put(p.neighbour_radius);
  const BuildReport& r = report_;
  w.putString(r.catalog_name);
  w.put(r.catalog_epoch_jyear);
  w.putString(r.catalog_path);
  w.put(r.catalog_depth_vmag);
  w.put(r.requested_mag_limit);
  for (std::size_t v : {r.catalog_entries, r.skipped_no_position, r.merge_candidates,
                        r.double_star_groups, r.stars_merged_away, r.after_mag_limit,
                        r.after_density})
    w.put(uint64_t(v));
  w.put(r.build_seconds);

  w.put(uint32_t(stars_.size()));
  for (const Star& s : stars_) {
    w.put(s.id);
    w.put(s.u_i.x());
    w.put(s.u_i.y());
    w.put(s.u_i.z());
    w.put(s.mag);
    if (format >= 4) w.put(s.bv);
  }
  const bool narrow = stars_.size() < 65536;
  w.put(uint8_t(narrow ? 2 : 4));
  auto putIndex = [&](uint32_t v) {
    if (narrow)
      w.put(uint16_t(v));
    else
      w.put(v);
  };
  w.put(uint64_t(pairs_.size()));
  for (const StarPair& pr : pairs_) {
    putIndex(pr.a);
    putIndex(pr.b);
    w.put(pr.theta);
  }
  for (uint32_t v : nbr_start_) w.put(v);
  for (uint32_t v : nbr_) putIndex(v);
  if (format >= 3) {
    w.put(uint32_t(screen_.size()));
    for (const ScreenStar& s : screen_) {
      w.put(s.u_i.x());
      w.put(s.u_i.y());
      w.put(s.u_i.z());
      w.put(s.mag);
    }
  }
  w.put(crc32Of(w.buf.data(), w.buf.size()));

  writeFileAtomically(path, w.buf.data(), w.buf.size());
}

namespace {

/// The file mapped read-only (MAP_POPULATE: its pages from the page cache in one call). A
/// plate solve per process loads its database every time: a read into a fresh buffer costs
/// a zeroed page fault per 4 KB on top of the copy (measured: 30 ms of 8 MB on this VM).
class MappedFile {
 public:
  explicit MappedFile(const std::string& path) {
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) throw InputError(path + ": cannot open star database");
    struct stat st {};
    if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
      ::close(fd);
      throw InputError(path + ": cannot read star database (not a regular file)");
    }
    size_ = std::size_t(st.st_size);
    if (size_ > 0) {
      void* p = ::mmap(nullptr, size_, PROT_READ, MAP_PRIVATE | MAP_POPULATE, fd, 0);
      if (p == MAP_FAILED) {
        ::close(fd);
        throw InputError(path + ": cannot read star database");
      }
      data_ = static_cast<const char*>(p);
    }
    ::close(fd);
  }
  ~MappedFile() {
    if (data_) ::munmap(const_cast<char*>(data_), size_);
  }
  MappedFile(const MappedFile&) = delete;
  MappedFile& operator=(const MappedFile&) = delete;
  std::string_view bytes() const { return {data_ ? data_ : "", size_}; }

 private:
  const char* data_ = nullptr;
  std::size_t size_ = 0;
};

// The whole file mapped (the load must take milliseconds), its magic, byte order, version
// and checksum verified; `body` is where the checksum starts.
std::string_view readVerified(const std::string& path, const MappedFile& file, std::size_t& body,
                              uint32_t& version) {
  const std::string_view bytes = file.bytes();
  if (bytes.size() < sizeof kMagic + 12 || std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0)
    throw InputError(path + ": not a star database (bad magic; build one with "
                     "`startracker catalog build`)");
  uint32_t bom;
  std::memcpy(&version, bytes.data() + sizeof kMagic, 4);
  std::memcpy(&bom, bytes.data() + sizeof kMagic + 4, 4);
  if (bom != kByteOrderMark)
    throw InputError(path + ": star database written on a host of the other byte order");
  if (version < kOldestReadableVersion || version > kFormatVersion)
    throw InputError(path + ": star database format version " + std::to_string(version) +
                     ", this program reads versions " + std::to_string(kOldestReadableVersion) +
                     " to " + std::to_string(kFormatVersion) +
                     "; rebuild it with `startracker catalog build`");
  body = bytes.size() - 4;
  uint32_t stored_crc;
  std::memcpy(&stored_crc, bytes.data() + body, 4);
  if (crc32Of(bytes.data(), body) != stored_crc)
    throw InputError(path + ": star database checksum mismatch (corrupt or truncated file)");
  return bytes;
}

void readParams(Reader& rd, DatabaseParams& p) {
  p.max_pair_angle = rd.get<double>("parameters");
  p.mag_limit = rd.get<double>("parameters");
  p.epoch_jyear = rd.get<double>("parameters");
  p.aberration = rd.get<uint8_t>("parameters") != 0;
  p.parallax = rd.get<uint8_t>("parameters") != 0;
  p.double_star_sep = rd.get<double>("parameters");
  p.max_stars_per_region = rd.get<int32_t>("parameters");
  p.region_radius = rd.get<double>("parameters");
  p.neighbour_radius = rd.get<double>("parameters");
}

void readReport(Reader& rd, uint32_t version, double mag_limit, BuildReport& r) {
  r.catalog_name = rd.getString("catalog name");
  r.catalog_epoch_jyear = rd.get<double>("report");
  if (version >= 2) {
    r.catalog_path = rd.getString("catalog path");
    r.catalog_depth_vmag = rd.get<double>("report");
    r.requested_mag_limit = rd.get<double>("report");
  } else {  // format 1 recorded the requested limit only, and neither file nor depth
    r.catalog_path.clear();
    r.catalog_depth_vmag = std::numeric_limits<double>::quiet_NaN();
    r.requested_mag_limit = mag_limit;
  }
  for (std::size_t* v : {&r.catalog_entries, &r.skipped_no_position, &r.merge_candidates,
                         &r.double_star_groups, &r.stars_merged_away, &r.after_mag_limit,
                         &r.after_density})
    *v = std::size_t(rd.get<uint64_t>("report"));
  r.build_seconds = rd.get<double>("report");
}

void readStars(Reader& rd, uint32_t version, std::vector<Star>& stars) {
  const uint32_t n = rd.get<uint32_t>("star count");
  rd.need(std::size_t(n) * (version >= 4 ? 36 : 32), "stars");
  stars.resize(n);
  for (Star& s : stars) {
    s.id = rd.get<uint32_t>("stars");
    const double x = rd.get<double>("stars"), y = rd.get<double>("stars"),
                 z = rd.get<double>("stars");
    s.u_i = Vec3(x, y, z);
    s.mag = rd.get<float>("stars");
    if (version >= 4) s.bv = rd.get<float>("stars");
  }
}

// Pairs of `width`-byte star indices (< n) and their angle, in one tight bulk decode.
void readPairs(Reader& rd, const std::string& path, std::size_t body, uint8_t width,
               uint32_t n, PairList& pairs) {
  const uint64_t np = rd.get<uint64_t>("pair count");
  const std::size_t pair_bytes = 2 * std::size_t(width) + 4;
  if (np > (body - rd.pos()) / pair_bytes) rd.need(body, "pairs");  // throws: truncated
  const char* pp = rd.raw(std::size_t(np) * pair_bytes, "pairs");
  // reserve + push_back: one pass over fresh memory (resize would zero it first).
  pairs.clear();
  pairs.reserve(std::size_t(np));
  bool bad_index = false;
  for (uint64_t k = 0; k < np; ++k) {  // tight bulk decode: the load must take milliseconds
    StarPair pr;
    if (width == 2) {
      uint16_t a, b;
      std::memcpy(&a, pp, 2);
      std::memcpy(&b, pp + 2, 2);
      pr.a = a;
      pr.b = b;
    } else {
      std::memcpy(&pr.a, pp, 4);
      std::memcpy(&pr.b, pp + 4, 4);
    }
    std::memcpy(&pr.theta, pp + 2 * width, 4);
    pp += pair_bytes;
    bad_index |= pr.b >= n || pr.a >= pr.b;
    pairs.push_back(pr);
  }
  if (bad_index) throw InputError(path + ": star database pair index out of range");
}

// Neighbour table: n + 1 monotonic offsets, then `width`-byte star indices (< n).
void readNeighbours(Reader& rd, const std::string& path, uint8_t width, uint32_t n,
                    std::vector<uint32_t>& start,
                    std::vector<uint32_t, HugePageAllocator<uint32_t>>& nbr) {
  const char* sp = rd.raw((std::size_t(n) + 1) * 4, "neighbour offsets");
  start.resize(std::size_t(n) + 1);
  std::memcpy(start.data(), sp, start.size() * 4);  // the file may not align them
  for (std::size_t i = 0; i < n; ++i)
    if (start[i + 1] < start[i] || start[0] != 0)
      throw InputError(path + ": star database neighbour offsets not monotonic");
  // The count comes from the file: check the bytes exist before allocating for them.
  const std::size_t count = start.back();
  const char* p = rd.raw(count * width, "neighbours");
  // reserve + push_back: one pass over fresh memory (resize would zero it first).
  nbr.clear();
  nbr.reserve(count);
  bool bad_index = false;
  for (std::size_t k = 0; k < count; ++k, p += width) {
    uint32_t v;
    if (width == 2) {
      uint16_t w;
      std::memcpy(&w, p, 2);
      v = w;
    } else {
      std::memcpy(&v, p, 4);
    }
    bad_index |= v >= n;
    nbr.push_back(v);
  }
  if (bad_index) throw InputError(path + ": star database neighbour index out of range");
}

void readScreenStars(Reader& rd, std::vector<ScreenStar>& screen) {
  const uint32_t n = rd.get<uint32_t>("screen star count");
  rd.need(std::size_t(n) * 28, "screen stars");
  screen.resize(n);
  for (ScreenStar& s : screen) {
    const double x = rd.get<double>("screen stars"), y = rd.get<double>("screen stars"),
                 z = rd.get<double>("screen stars");
    s.u_i = Vec3(x, y, z);
    s.mag = rd.get<float>("screen stars");
  }
}

}  // namespace

StarDatabase StarDatabase::load(const std::string& path) {
  std::size_t body = 0;
  uint32_t version = 0;
  const MappedFile file(path);
  const std::string_view bytes = readVerified(path, file, body, version);
  Reader rd(path, bytes, body);
  rd.need(sizeof kMagic + 8, "header");
  rd.get<uint64_t>("magic");
  rd.get<uint64_t>("version");
  StarDatabase db;
  readParams(rd, db.params_);
  BuildReport& r = db.report_;
  readReport(rd, version, db.params_.mag_limit, r);
  readStars(rd, version, db.stars_);
  const uint32_t n = static_cast<uint32_t>(db.stars_.size());
  const uint8_t width = rd.get<uint8_t>("index width");
  if (width != 2 && width != 4)
    throw InputError(path + ": star database has an invalid index width " + std::to_string(width));
  readPairs(rd, path, body, width, n, db.pairs_);
  readNeighbours(rd, path, width, n, db.nbr_start_, db.nbr_);
  if (version >= 3) readScreenStars(rd, db.screen_);
  r.screen_stars = db.screen_.size();
  if (rd.pos() != body)
    throw InputError(path + ": star database has " + std::to_string(body - rd.pos()) +
                     " unexpected bytes before the checksum");
  db.buildIndexes();
  db.pair_kv_.build(db.pairs_.size(), [&](std::size_t k) { return double(db.pairs_[k].theta); });
  r.pairs = db.pairs_.size();
  r.kvector_size = db.pair_kv_.size();
  r.neighbour_entries = db.nbr_.size();
  return db;
}

}  // namespace st

// The LAS 1.0-1.4 reader (formats 0-10, CRS from WKT or GeoKeys VLRs; LAZ
// point data decoded by core/io/laz into the same records) and the LAS writer.
#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <optional>

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/error.h"
#include "core/io/crs.h"
#include "core/io/laz/item_reader.h"
#include "core/io/laz/laz_reader.h"
#include "core/io/laz/laz_writer.h"
#include "core/io/point_io.h"
#include "core/io/point_io_detail.h"
#include "core/io/read_limits.h"

namespace c3d {

using namespace point_io_detail;

namespace {

// ---------------------------------------------------------------- LAS ----

// Header scales and offsets a real survey can have. Geographic LAS use 1e-7
// (degrees); below 1e-9 the 32-bit records span under +-2.1 units, no survey.
// Above 1 unit the coordinates are coarser than any building. No projected or
// geocentric coordinate exceeds 1e9 (Web Mercator reaches 2e7 m).
constexpr double kMinLasScale = 1e-9, kMaxLasScale = 1.0;
constexpr double kMaxLasOffset = 1e9;

std::string number_text(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

// A coordinate in full, to the centimetre (%g would round 9240012 to 9.24e+06).
std::string coordinate_text(double v) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.2f", v);
  return buf;
}

// Point record sizes per format 0-10 (LAS 1.4 R15, table 7ff).
constexpr std::array<int, 11> kLasRecordSize = {20, 28, 26, 34, 57, 63, 30, 36, 38, 59, 67};

struct LasHeader {
  int major = 1, minor = 0, format = 0, record_length = 0;
  bool compressed = false;  // LAZ: the point data is LASzip chunks
  uint16_t header_size = 0, global_encoding = 0;
  uint32_t point_offset = 0, vlr_count = 0, evlr_count = 0;
  uint64_t point_count = 0, evlr_offset = 0;
  double scale[3], offset[3];
};

// The point records of an uncompressed file end where the EVLRs begin (LAS
// 1.4, when it has some behind the points) or at the end of the file. Bytes
// left over mean the point count, the record length or the point data offset
// is not the file's: reading on would silently drop points or read records
// out of step (every LAS of ../shared/data ends exactly).
void check_points_fill_their_bytes(const std::string& path, const LasHeader& h, uint64_t file_size) {
  const uint64_t points_end = h.point_offset + h.point_count * h.record_length;
  const bool evlrs_behind = h.evlr_count > 0 && h.evlr_offset >= points_end && h.evlr_offset <= file_size;
  const uint64_t data_end = evlrs_behind ? h.evlr_offset : file_size;
  if (data_end == points_end) return;
  throw InputError(path, "the header's " + std::to_string(h.point_count) + " points of " +
                             std::to_string(h.record_length) + " bytes from offset " + std::to_string(h.point_offset) +
                             " leave " + std::to_string(data_end - points_end) + " bytes before " +
                             (evlrs_behind ? "the EVLRs" : "the end of the file") +
                             ": the point count, record length or point data offset is not the file's");
}

// buf: the file, or its first bytes up to the point data (file_size: the whole file's).
LasHeader parse_las_header(const std::string& path, const std::vector<char>& buf, size_t file_size) {
  if (buf.size() < 4 || std::memcmp(buf.data(), "LASF", 4) != 0)
    throw InputError(path, "not a LAS file (no LASF signature)");
  if (buf.size() < 227)
    throw InputError(path, "truncated LAS file: " + std::to_string(buf.size()) +
                               " bytes, shorter than a LAS header (227 bytes)");
  const char* p = buf.data();
  LasHeader h;
  h.global_encoding = get<uint16_t>(p + 6);
  h.major = uint8_t(p[24]);
  h.minor = uint8_t(p[25]);
  h.header_size = get<uint16_t>(p + 94);
  h.point_offset = get<uint32_t>(p + 96);
  h.vlr_count = get<uint32_t>(p + 100);
  int raw_format = uint8_t(p[104]);
  h.record_length = get<uint16_t>(p + 105);
  h.point_count = get<uint32_t>(p + 107);
  for (int i = 0; i < 3; ++i) {
    h.scale[i] = get<double>(p + 131 + 8 * i);
    h.offset[i] = get<double>(p + 155 + 8 * i);
  }
  if (h.major != 1 || h.minor > 4)
    throw InputError(path, "unsupported LAS version " + std::to_string(h.major) + "." +
                               std::to_string(h.minor) + " (1.0-1.4 are read)");
  h.compressed = raw_format & 0xC0;  // LASzip sets the two high bits of the format byte
  raw_format &= 0x3F;
  if (raw_format > 10)
    throw InputError(path, "unknown LAS point format " + std::to_string(raw_format) +
                               " (0-10 are defined)");
  h.format = raw_format;
  if (h.header_size < 227 || h.header_size > buf.size())
    throw InputError(path, "truncated LAS file: header size " + std::to_string(h.header_size) +
                               " does not fit the file");
  if (h.minor >= 4 && h.header_size >= 375) {
    h.evlr_offset = get<uint64_t>(p + 235);
    h.evlr_count = get<uint32_t>(p + 243);
    uint64_t count64 = get<uint64_t>(p + 247);
    if (count64 != 0 || h.point_count == 0) h.point_count = count64;
  }
  if (h.record_length < kLasRecordSize[h.format])
    throw InputError(path, "point record length " + std::to_string(h.record_length) +
                               " is too short for point format " + std::to_string(h.format));
  for (int i = 0; i < 3; ++i) {
    const std::string axis(1, "XYZ"[i]);
    if (!std::isfinite(h.scale[i]) || !std::isfinite(h.offset[i]) || h.scale[i] == 0)
      throw InputError(path, "NaN/inf or zero " + axis + " scale/offset in the LAS header, coordinates would be "
                             "NaN/inf");
    if (h.scale[i] < kMinLasScale || h.scale[i] > kMaxLasScale)
      throw InputError(path, "implausible " + axis + " scale " + number_text(h.scale[i]) +
                                 " in the LAS header (must be positive, " + number_text(kMinLasScale) + ".." +
                                 number_text(kMaxLasScale) + ")");
    if (std::abs(h.offset[i]) > kMaxLasOffset)
      throw InputError(path, "implausible " + axis + " offset " + number_text(h.offset[i]) +
                                 " in the LAS header (beyond +-" + number_text(kMaxLasOffset) + ")");
  }
  if (h.point_offset < h.header_size || h.point_offset > file_size)
    throw InputError(path, "truncated LAS file: point data offset " +
                               std::to_string(h.point_offset) + " lies beyond the end of the file (" +
                               std::to_string(file_size) + " bytes)");
  uint64_t available = (file_size - h.point_offset) / h.record_length;
  if (!h.compressed && h.point_count > available)
    throw InputError(path, "truncated LAS file: header point count " +
                               std::to_string(h.point_count) + " is larger than the file holds (" +
                               std::to_string(available) + " complete points)");
  if (!h.compressed) check_points_fill_their_bytes(path, h, file_size);
  return h;
}

// GeoKeyDirectory (record 34735): keys of 4 uint16 after a 4-uint16 header.
int epsg_from_geokeys(const char* data, size_t size) {
  size_t n = size / 2;
  if (n < 4) return 0;
  int keys = get<uint16_t>(data + 6);
  int projected = 0, geographic = 0;
  for (int k = 0; k < keys && 4 + 4 * k + 3 < int(n); ++k) {
    const char* e = data + 8 + 8 * k;
    int id = get<uint16_t>(e), location = get<uint16_t>(e + 2), value = get<uint16_t>(e + 6);
    if (location != 0) continue;  // EPSG codes are stored inline
    if (id == 3072) projected = value;
    if (id == 2048) geographic = value;
  }
  return projected && projected != 32767 ? projected
         : geographic && geographic != 32767 ? geographic : 0;
}

// Calls visit(record header, payload length, payload) for each VLR and EVLR.
template <typename Visit>
void visit_vlrs(const std::string& path, const std::vector<char>& buf, const LasHeader& h, Visit visit) {
  size_t pos = h.header_size;
  for (uint32_t i = 0; i < h.vlr_count; ++i) {
    if (pos + 54 > h.point_offset)
      throw InputError(path, "truncated LAS file: VLR " + std::to_string(i) +
                                 " runs past the start of the point data");
    uint16_t length = get<uint16_t>(buf.data() + pos + 20);
    if (pos + 54 + length > buf.size())
      throw InputError(path, "truncated LAS file: VLR " + std::to_string(i) + " runs past the end");
    if (pos + 54 + length > h.point_offset)
      throw InputError(path, "VLR " + std::to_string(i) + " runs past the start of the point data (offset " +
                                 std::to_string(h.point_offset) + "): the VLR or the offset is not the file's");
    visit(buf.data() + pos, length, buf.data() + pos + 54);
    pos += 54 + length;
  }
  pos = h.evlr_offset;  // any 64-bit value: compared without overflow
  for (uint32_t i = 0; i < h.evlr_count && pos <= buf.size() && buf.size() - pos >= 60; ++i) {
    uint64_t length = get<uint64_t>(buf.data() + pos + 20);
    if (length > buf.size() - pos - 60) break;  // a damaged EVLR does not spoil the points
    visit(buf.data() + pos, length, buf.data() + pos + 60);
    pos += 60 + length;
  }
}

std::string vlr_user(const char* rec) { return std::string(rec + 2, strnlen(rec + 2, 16)); }

// CRS from the VLRs and EVLRs: OGC WKT (2112) wins over GeoKeys (34735).
std::string las_crs(const std::string& path, const std::vector<char>& buf, const LasHeader& h) {
  std::string wkt;
  int epsg = 0;
  visit_vlrs(path, buf, h, [&](const char* rec, uint64_t length, const char* where) {
    int id = get<uint16_t>(rec + 18);
    if (vlr_user(rec) != "LASF_Projection") return;
    if (id == 2112) wkt.assign(where, strnlen(where, length));
    if (id == 34735) epsg = epsg_from_geokeys(where, length);
  });
  if (!wkt.empty()) return wkt;
  if (epsg) {
    try {
      return wkt_from_epsg(epsg);
    } catch (const std::exception&) {
      throw InputError(path, "GeoKeys name EPSG:" + std::to_string(epsg) + ", unknown to PROJ");
    }
  }
  return {};
}

// -------------------------------------------------------------- write ----

int min_minor_for(int format) { return format >= 6 ? 4 : format >= 4 ? 3 : format >= 2 ? 2 : 0; }

// VLR with the CRS: OGC WKT for formats 6-10 (mandatory there), GeoKeys for
// 0-5 when the CRS has an EPSG code (what pre-1.4 readers understand).
std::string crs_vlr(const std::string& wkt, int format, bool* is_wkt) {
  if (wkt.empty()) return {};
  int epsg = format < 6 ? epsg_of(wkt) : 0;
  std::string vlr(54, '\0');
  std::memcpy(&vlr[2], "LASF_Projection", 15);
  std::string payload;
  if (epsg) {
    bool geographic = epsg >= 4000 && epsg < 5000;  // EPSG geographic 2D codes
    uint16_t keys[] = {1, 1, 0, 3,
                       1024, 0, 1, uint16_t(geographic ? 2 : 1),  // GTModelType
                       1025, 0, 1, 1,                             // RasterPixelIsArea
                       uint16_t(geographic ? 2048 : 3072), 0, 1, uint16_t(epsg)};
    payload.assign(reinterpret_cast<const char*>(keys), sizeof(keys));
    put<uint16_t>(vlr, 18, 34735);
    *is_wkt = false;
  } else {
    payload = wkt + '\0';
    put<uint16_t>(vlr, 18, 2112);
    *is_wkt = true;
  }
  put<uint16_t>(vlr, 20, uint16_t(payload.size()));
  std::memcpy(&vlr[22], "CRS", 3);
  return vlr + payload;
}

// The point records of a LAZ file, decoded as an uncompressed file holds them.
std::vector<uint8_t> laz_records(const std::string& path, const std::vector<char>& buf, const LasHeader& h) {
  try {
    const char* vlr = nullptr;
    uint64_t vlr_length = 0;
    visit_vlrs(path, buf, h, [&](const char* rec, uint64_t length, const char* where) {
      if (vlr_user(rec) == laz::kLaszipUserId && get<uint16_t>(rec + 18) == laz::kLaszipRecordId)
        vlr = where, vlr_length = length;
    });
    if (!vlr) throw laz::FormatError("compressed points but no LASzip VLR");
    laz::PointData in;
    in.file = reinterpret_cast<const uint8_t*>(buf.data());
    in.file_size = buf.size();
    in.point_offset = h.point_offset;
    in.count = h.point_count;
    in.record_length = uint32_t(h.record_length);
    return laz::decode_points(in, laz::parse_laszip_vlr(reinterpret_cast<const uint8_t*>(vlr), vlr_length));
  } catch (const laz::FormatError& e) {
    throw InputError(path, std::string("LAZ: ") + e.what());
  }
}

// Appends n records (the first is point first_index of the file) to cloud.
void append_records(const std::string& path, const LasHeader& h, const char* rec, size_t n, size_t first_index,
                    PointCloud& cloud) {
  const size_t at = cloud.points.size();
  cloud.points.resize(at + n);
  cloud.classes.resize(at + n);
  cloud.returns.resize(at + n);
  // Formats 6-10 carry a full classification byte (classes >= 32 such as 64
  // survive); 0-5 keep the class in the low 5 bits beside three flags.
  const bool extended = h.format >= 6;
  const int class_at = extended ? 16 : 15;
  const uint8_t class_mask = extended ? 0xFF : 0x1F;
  for (size_t i = 0; i < n; ++i, rec += h.record_length) {
    Vec3& p = cloud.points[at + i];
    p = Vec3(get<int32_t>(rec) * h.scale[0] + h.offset[0], get<int32_t>(rec + 4) * h.scale[1] + h.offset[1],
             get<int32_t>(rec + 8) * h.scale[2] + h.offset[2]);
    check_coordinates(path, p.x(), p.y(), p.z(), first_index + i);
    cloud.classes[at + i] = uint8_t(rec[class_at]) & class_mask;
    const uint8_t r = uint8_t(rec[14]);  // return number and number of returns: 4 + 4 bits, or 3 + 3
    cloud.returns[at + i] = extended ? pack_returns(r & 15, r >> 4) : pack_returns(r & 7, (r >> 3) & 7);
  }
}

// A file mapped read-only. A streamed file hands back the pages it has read
// (release_before), so it is never resident whole.
class MappedFile {
 public:
  explicit MappedFile(const std::string& path) {
    check_regular_file(path);
    fd_ = ::open(path.c_str(), O_RDONLY);
    if (fd_ < 0) throw InputError(path, "cannot open file (" + std::string(std::strerror(errno)) + ")");
    struct stat st {};
    if (::fstat(fd_, &st) != 0 || st.st_size <= 0) {
      ::close(fd_);
      throw InputError(path, "empty file");
    }
    size_ = size_t(st.st_size);
    void* at = ::mmap(nullptr, size_, PROT_READ, MAP_PRIVATE, fd_, 0);
    if (at == MAP_FAILED) {
      ::close(fd_);
      throw InputError(path, "cannot map file (" + std::string(std::strerror(errno)) + ")");
    }
    data_ = static_cast<const char*>(at);
    ::madvise(at, size_, MADV_SEQUENTIAL);
  }
  ~MappedFile() {
    ::munmap(const_cast<char*>(data_), size_);
    ::close(fd_);
  }
  MappedFile(const MappedFile&) = delete;
  MappedFile& operator=(const MappedFile&) = delete;
  const char* data() const { return data_; }
  size_t size() const { return size_; }
  void release_before(size_t offset) {
    const size_t page = size_t(::sysconf(_SC_PAGESIZE)), end = std::min(offset, size_) / page * page;
    if (end <= released_) return;
    ::madvise(const_cast<char*>(data_) + released_, end - released_, MADV_DONTNEED);
    released_ = end;
  }

 private:
  int fd_ = -1;
  const char* data_ = nullptr;
  size_t size_ = 0, released_ = 0;
};

// The header and the VLRs (the bytes before the point data), parsed.
struct LasPrefix {
  std::vector<char> bytes;
  LasHeader header;
};

LasPrefix las_prefix(const std::string& path, const MappedFile& file) {
  const size_t offset = file.size() >= 100 ? get<uint32_t>(file.data() + 96) : 0;
  LasPrefix p;
  p.bytes.assign(file.data(), file.data() + std::min(file.size(), std::max<size_t>(375, offset)));
  p.header = parse_las_header(path, p.bytes, file.size());
  return p;
}

// The CRS from the VLRs, else from the EVLRs after the points (copied on their own).
std::string prefix_crs(const std::string& path, const LasPrefix& p, const MappedFile& file) {
  std::string wkt = las_crs(path, p.bytes, p.header);
  if (!wkt.empty() || p.header.evlr_count == 0 || p.header.evlr_offset >= file.size()) return wkt;
  const std::vector<char> tail(file.data() + p.header.evlr_offset, file.data() + file.size());
  LasHeader evlrs = p.header;
  evlrs.vlr_count = 0;
  evlrs.evlr_offset = 0;
  return las_crs(path, tail, evlrs);
}

void stream_laz(const std::string& path, const LasPrefix& p, MappedFile& file,
                const std::function<void(const char*, size_t)>& emit) {
  try {
    const char* vlr = nullptr;
    uint64_t vlr_length = 0;
    visit_vlrs(path, p.bytes, p.header, [&](const char* rec, uint64_t length, const char* where) {
      if (vlr_user(rec) == laz::kLaszipUserId && get<uint16_t>(rec + 18) == laz::kLaszipRecordId)
        vlr = where, vlr_length = length;
    });
    if (!vlr) throw laz::FormatError("compressed points but no LASzip VLR");
    laz::PointData in;
    in.file = reinterpret_cast<const uint8_t*>(file.data());
    in.file_size = file.size();
    in.point_offset = p.header.point_offset;
    in.count = p.header.point_count;
    in.record_length = uint32_t(p.header.record_length);
    laz::decode_points_by_chunk(in, laz::parse_laszip_vlr(reinterpret_cast<const uint8_t*>(vlr), vlr_length),
                                [&](const uint8_t* records, uint64_t n, uint64_t bytes_end) {
                                  emit(reinterpret_cast<const char*>(records), size_t(n));
                                  file.release_before(bytes_end);
                                });
  } catch (const laz::FormatError& e) {
    throw InputError(path, std::string("LAZ: ") + e.what());
  }
}

}  // namespace

void point_io_detail::stream_las(const std::string& path, size_t block_points,
                                 const std::function<void(const PointCloud&)>& block) {
  MappedFile file(path);
  const LasPrefix p = las_prefix(path, file);
  const LasHeader& h = p.header;
  PointCloud out;
  out.source = path;
  out.crs_wkt = prefix_crs(path, p, file);
  size_t index = 0;
  auto emit = [&](const char* rec, size_t n) {
    out.points.clear();
    out.classes.clear();
    out.returns.clear();
    append_records(path, h, rec, n, index, out);
    index += n;
    block(out);
  };
  if (h.compressed) return stream_laz(path, p, file, emit);
  for (uint64_t done = 0; done < h.point_count; done += block_points) {
    const size_t n = size_t(std::min<uint64_t>(block_points, h.point_count - done));
    emit(file.data() + h.point_offset + done * h.record_length, n);
    file.release_before(h.point_offset + (done + n) * h.record_length);
  }
}

namespace {

// How many records of an uncompressed file are checked against its header's bounds.
constexpr uint64_t kBoundsSamples = 4096;

// The first of n records (rec) that lies outside e by more than half a
// coordinate step, if any: its plan position.
std::optional<Vec2> outside_bounds(const LasHeader& h, const char* rec, size_t n, size_t stride, const CloudExtent& e) {
  const double tx = h.scale[0] / 2 + 1e-9, ty = h.scale[1] / 2 + 1e-9;
  for (size_t i = 0; i < n; ++i, rec += stride) {
    const double x = get<int32_t>(rec) * h.scale[0] + h.offset[0], y = get<int32_t>(rec + 4) * h.scale[1] + h.offset[1];
    if (x < e.min_x - tx || x > e.max_x + tx || y < e.min_y - ty || y > e.max_y + ty) return Vec2(x, y);
  }
  return std::nullopt;
}

// A point of the file outside the header's bounds, from a sample: an
// uncompressed file's records evenly through it, a LAZ file's first chunk.
// Writers that left the bounds stale (or zero) would make a tile look out of
// the parcels' reach, and it would not be read.
std::optional<Vec2> sampled_outside(const std::string& path, const LasPrefix& p, MappedFile& file,
                                    const CloudExtent& e) {
  const LasHeader& h = p.header;
  if (h.point_count == 0) return std::nullopt;
  if (!h.compressed) {
    const uint64_t n = std::min(h.point_count, kBoundsSamples), step = std::max<uint64_t>(1, h.point_count / n);
    if (h.point_offset + ((n - 1) * step + 1) * uint64_t(h.record_length) > file.size()) return std::nullopt;
    return outside_bounds(h, file.data() + h.point_offset, size_t(n), size_t(step * uint64_t(h.record_length)), e);
  }
  struct FirstChunkRead {};  // decoding stops after the first chunk
  std::optional<Vec2> out;
  try {
    stream_laz(path, p, file, [&](const char* rec, size_t n) {
      out = outside_bounds(h, rec, n, size_t(h.record_length), e);
      throw FirstChunkRead{};
    });
  } catch (const FirstChunkRead&) {
  }
  return out;
}

}  // namespace

std::optional<CloudExtent> point_io_detail::las_header_extent(const std::string& path) {
  MappedFile file(path);
  const LasPrefix p = las_prefix(path, file);
  const char* b = p.bytes.data();
  CloudExtent e;
  e.crs_wkt = prefix_crs(path, p, file);
  e.points = p.header.point_count;
  e.max_x = get<double>(b + 179), e.min_x = get<double>(b + 187);
  e.max_y = get<double>(b + 195), e.min_y = get<double>(b + 203);
  const bool usable = std::isfinite(e.min_x) && std::isfinite(e.max_x) && std::isfinite(e.min_y) &&
                      std::isfinite(e.max_y) && e.min_x <= e.max_x && e.min_y <= e.max_y;
  if (!usable && e.points > 0) return std::nullopt;
  if (const auto q = sampled_outside(path, p, file, e)) {
    e.note = "a point at " + coordinate_text(q->x()) + ", " + coordinate_text(q->y()) +
             " lies outside the header's bounds (x " + coordinate_text(e.min_x) + " to " + coordinate_text(e.max_x) +
             ", y " + coordinate_text(e.min_y) + " to " + coordinate_text(e.max_y) + "): extent read from the points";
  }
  return e;
}

PointCloud point_io_detail::read_las(const std::string& path) {
  std::vector<char> buf = slurp(path);
  LasHeader h = parse_las_header(path, buf, buf.size());
  PointCloud cloud;
  cloud.source = path;
  cloud.crs_wkt = las_crs(path, buf, h);
  std::vector<uint8_t> decoded;
  if (h.compressed) decoded = laz_records(path, buf, h);
  const char* rec = h.compressed ? reinterpret_cast<const char*>(decoded.data()) : buf.data() + h.point_offset;
  append_records(path, h, rec, h.point_count, 0, cloud);
  return cloud;
}

std::vector<uint8_t> read_las_records(const std::string& path) {
  std::vector<char> buf = slurp(path);
  LasHeader h = parse_las_header(path, buf, buf.size());
  if (h.compressed) return laz_records(path, buf, h);
  const uint8_t* begin = reinterpret_cast<const uint8_t*>(buf.data()) + h.point_offset;
  return std::vector<uint8_t>(begin, begin + h.point_count * h.record_length);
}

namespace {

// The bytes of an uncompressed LAS file holding the cloud.
std::string las_file_bytes(const std::string& path, const PointCloud& cloud, int point_format, int minor_version) {
  if (point_format < 0 || point_format > 10)
    throw InputError(path, "unknown LAS point format " + std::to_string(point_format));
  if (minor_version < min_minor_for(point_format) || minor_version > 4)
    throw InputError(path, "point format " + std::to_string(point_format) + " needs LAS 1." +
                               std::to_string(min_minor_for(point_format)) + " or later");
  const size_t n = cloud.points.size();
  const bool extended = point_format >= 6;
  if (!extended && n > 0xFFFFFFFFull)
    throw InputError(path, "more than 2^32 points need point format 6-10");
  Vec3 lo = Vec3::Constant(0), hi = Vec3::Constant(0);
  if (n) {
    lo = hi = cloud.points[0];
    for (const Vec3& p : cloud.points) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  }
  // Millimetre resolution around a rounded offset; coarser only for huge extents.
  double scale[3], offset[3];
  for (int i = 0; i < 3; ++i) {
    offset[i] = std::round((lo[i] + hi[i]) / 2);
    scale[i] = 0.001;
    while ((hi[i] - lo[i]) / 2 / scale[i] > 2.0e9) scale[i] *= 10;
  }
  const int header_size = minor_version >= 4 ? 375 : minor_version == 3 ? 235 : 227;
  bool is_wkt = false;
  const std::string vlr = crs_vlr(cloud.crs_wkt, point_format, &is_wkt);
  const int record = kLasRecordSize[point_format];
  const size_t point_offset = header_size + vlr.size();

  std::string out(point_offset + n * record, '\0');
  std::memcpy(&out[0], "LASF", 4);
  put<uint16_t>(out, 6, uint16_t(is_wkt && minor_version >= 4 ? 16 : 0));  // WKT bit
  out[24] = 1;
  out[25] = char(minor_version);
  std::memcpy(&out[26], "cadastre3d", 10);
  std::memcpy(&out[58], "cadastre3d write_las", 20);
  put<uint16_t>(out, 94, uint16_t(header_size));
  put<uint32_t>(out, 96, uint32_t(point_offset));
  put<uint32_t>(out, 100, vlr.empty() ? 0u : 1u);
  out[104] = char(point_format);
  put<uint16_t>(out, 105, uint16_t(record));
  const bool has_returns = cloud.returns.size() == n;
  std::array<uint64_t, 15> by_return{};  // points per return number; formats 6-10 leave the 32-bit counts 0
  for (size_t i = 0; i < n; ++i) ++by_return[has_returns ? std::max(1, return_number(cloud.returns[i])) - 1 : 0];
  put<uint32_t>(out, 107, extended ? 0u : uint32_t(n));
  for (int r = 0; r < 5; ++r) put<uint32_t>(out, 111 + 4 * r, extended ? 0u : uint32_t(by_return[size_t(r)]));
  for (int i = 0; i < 3; ++i) {
    put<double>(out, 131 + 8 * i, scale[i]);
    put<double>(out, 155 + 8 * i, offset[i]);
    put<double>(out, 179 + 16 * i, hi[i]);
    put<double>(out, 187 + 16 * i, lo[i]);
  }
  if (minor_version >= 4) {
    put<uint64_t>(out, 247, n);
    for (int r = 0; r < 15; ++r) put<uint64_t>(out, 255 + 8 * r, by_return[size_t(r)]);
  }
  std::memcpy(&out[header_size], vlr.data(), vlr.size());
  const bool has_classes = cloud.classes.size() == n;
  for (size_t i = 0; i < n; ++i) {
    const size_t r = point_offset + i * record;
    for (int k = 0; k < 3; ++k)
      put<int32_t>(out, r + 4 * k, int32_t(std::llround((cloud.points[i][k] - offset[k]) / scale[k])));
    const uint8_t cls = has_classes ? cloud.classes[i] : 1;  // 1 = unclassified
    const uint8_t ret = has_returns ? cloud.returns[i] : pack_returns(1, 1);
    if (extended) {
      out[r + 14] = char(return_number(ret) | number_of_returns(ret) << 4);
      out[r + 16] = char(cls);
    } else {
      out[r + 14] = char((return_number(ret) & 7) | (number_of_returns(ret) & 7) << 3);
      out[r + 15] = char(cls & 0x1F);
    }
  }
  return out;
}

void write_file(const std::string& path, const char* data, size_t size) {
  std::unique_ptr<FILE, int (*)(FILE*)> f(std::fopen(path.c_str(), "wb"), &std::fclose);
  if (!f || std::fwrite(data, 1, size, f.get()) != size || std::fflush(f.get()) != 0)
    throw InputError(path, "cannot write the file (" + std::string(std::strerror(errno)) + ")");
}

}  // namespace

void write_las(const std::string& path, const PointCloud& cloud, int point_format, int minor_version) {
  const std::string out = las_file_bytes(path, cloud, point_format, minor_version);
  write_file(path, out.data(), out.size());
}

void write_laz(const std::string& path, const PointCloud& cloud, int point_format, int minor_version) {
  const std::string las = las_file_bytes(path, cloud, point_format, minor_version);
  std::vector<uint8_t> laz;
  try {
    laz = laz::compress_las(std::vector<uint8_t>(las.begin(), las.end()));
  } catch (const laz::FormatError& e) {
    throw InputError(path, std::string("LAZ: ") + e.what());
  }
  write_file(path, reinterpret_cast<const char*>(laz.data()), laz.size());
}

}  // namespace c3d

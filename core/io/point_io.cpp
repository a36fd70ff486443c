// Point-cloud readers (own LAS 1.0-1.4 reader, PLY, PCD via PCL, XYZ/CSV) and
// the LAS writer. Files are read with one bulk fread and parsed from memory.
#include "core/io/point_io.h"

#include <pcl/PCLPointCloud2.h>
#include <pcl/io/pcd_io.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <sstream>

#include "core/io/crs.h"
#include "core/error.h"

namespace c3d {
namespace {

namespace fs = std::filesystem;

std::string lower(std::string s) {
  for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::string extension(const std::string& path) { return lower(fs::path(path).extension().string()); }

// The whole file in memory: one fread is the fastest way through the page cache.
std::vector<char> slurp(const std::string& path) {
  std::unique_ptr<FILE, int (*)(FILE*)> f(std::fopen(path.c_str(), "rb"), &std::fclose);
  if (!f) throw InputError(path, "cannot open file (" + std::string(std::strerror(errno)) + ")");
  std::fseek(f.get(), 0, SEEK_END);
  long size = std::ftell(f.get());
  std::fseek(f.get(), 0, SEEK_SET);
  if (size <= 0) throw InputError(path, "empty file");
  std::vector<char> buf(static_cast<size_t>(size));
  if (std::fread(buf.data(), 1, buf.size(), f.get()) != buf.size())
    throw InputError(path, "read error");
  return buf;
}

template <typename T>
T get(const char* p) {  // unaligned little-endian load (x86 and ARM are little-endian)
  T v;
  std::memcpy(&v, p, sizeof(T));
  return v;
}

template <typename T>
void put(std::string& out, size_t pos, T v) {
  std::memcpy(&out[pos], &v, sizeof(T));
}

void check_finite(const std::string& path, double x, double y, double z, size_t index) {
  if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z))
    throw InputError(path, "NaN/inf coordinate at point " + std::to_string(index));
}

// ---------------------------------------------------------------- LAS ----

// Point record sizes per format 0-10 (LAS 1.4 R15, table 7ff).
constexpr std::array<int, 11> kLasRecordSize = {20, 28, 26, 34, 57, 63, 30, 36, 38, 59, 67};

struct LasHeader {
  int major = 1, minor = 0, format = 0, record_length = 0;
  uint16_t header_size = 0, global_encoding = 0;
  uint32_t point_offset = 0, vlr_count = 0, evlr_count = 0;
  uint64_t point_count = 0, evlr_offset = 0;
  double scale[3], offset[3];
};

LasHeader parse_las_header(const std::string& path, const std::vector<char>& buf) {
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
  if (raw_format & 0xC0)  // LASzip sets the two high bits of the format byte
    throw InputError(path, "LAZ-compressed points are not supported; convert first, e.g. "
                           "`pdal translate in.laz out.las` or `las2las -i in.laz -o out.las`");
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
  for (int i = 0; i < 3; ++i)
    if (!std::isfinite(h.scale[i]) || !std::isfinite(h.offset[i]) || h.scale[i] == 0)
      throw InputError(path, "NaN/inf or zero scale/offset in the LAS header, coordinates would be "
                             "NaN/inf");
  if (h.point_offset < h.header_size || h.point_offset > buf.size())
    throw InputError(path, "truncated LAS file: point data offset " +
                               std::to_string(h.point_offset) + " lies beyond the end of the file (" +
                               std::to_string(buf.size()) + " bytes)");
  uint64_t available = (buf.size() - h.point_offset) / h.record_length;
  if (h.point_count > available)
    throw InputError(path, "truncated LAS file: header point count " +
                               std::to_string(h.point_count) + " is larger than the file holds (" +
                               std::to_string(available) + " complete points)");
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

// CRS from the VLRs and EVLRs: OGC WKT (2112) wins over GeoKeys (34735).
std::string las_crs(const std::string& path, const std::vector<char>& buf, const LasHeader& h) {
  std::string wkt;
  int epsg = 0;
  auto visit = [&](const char* rec, uint64_t length, const char* where) {
    std::string user(rec + 2, strnlen(rec + 2, 16));
    int id = get<uint16_t>(rec + 18);
    if (user != "LASF_Projection") return;
    if (id == 2112) wkt.assign(where, strnlen(where, length));
    if (id == 34735) epsg = epsg_from_geokeys(where, length);
  };
  size_t pos = h.header_size;
  for (uint32_t i = 0; i < h.vlr_count; ++i) {
    if (pos + 54 > h.point_offset)
      throw InputError(path, "truncated LAS file: VLR " + std::to_string(i) +
                                 " runs past the start of the point data");
    uint16_t length = get<uint16_t>(buf.data() + pos + 20);
    if (pos + 54 + length > buf.size())
      throw InputError(path, "truncated LAS file: VLR " + std::to_string(i) + " runs past the end");
    visit(buf.data() + pos, length, buf.data() + pos + 54);
    pos += 54 + length;
  }
  pos = h.evlr_offset;
  for (uint32_t i = 0; i < h.evlr_count && pos + 60 <= buf.size(); ++i) {
    uint64_t length = get<uint64_t>(buf.data() + pos + 20);
    if (length > buf.size() - pos - 60) break;  // a damaged EVLR does not spoil the points
    visit(buf.data() + pos, length, buf.data() + pos + 60);
    pos += 60 + length;
  }
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

PointCloud read_las(const std::string& path) {
  std::vector<char> buf = slurp(path);
  LasHeader h = parse_las_header(path, buf);
  PointCloud cloud;
  cloud.source = path;
  cloud.crs_wkt = las_crs(path, buf, h);
  size_t n = h.point_count;
  cloud.points.resize(n);
  cloud.classes.resize(n);
  // Formats 6-10 carry a full classification byte (classes >= 32 such as 64
  // survive); 0-5 keep the class in the low 5 bits beside three flags.
  const bool extended = h.format >= 6;
  const int class_at = extended ? 16 : 15;
  const uint8_t class_mask = extended ? 0xFF : 0x1F;
  const char* rec = buf.data() + h.point_offset;
  for (size_t i = 0; i < n; ++i, rec += h.record_length) {
    cloud.points[i] = Vec3(get<int32_t>(rec) * h.scale[0] + h.offset[0],
                           get<int32_t>(rec + 4) * h.scale[1] + h.offset[1],
                           get<int32_t>(rec + 8) * h.scale[2] + h.offset[2]);
    cloud.classes[i] = uint8_t(rec[class_at]) & class_mask;
  }
  return cloud;
}

// ---------------------------------------------------------------- PLY ----

enum class PlyType { I8, U8, I16, U16, I32, U32, F32, F64 };

struct PlyProperty {
  std::string name;
  PlyType type;
  int offset = 0;  // byte offset within a binary vertex record
  bool is_list = false;
};

struct PlyElement {
  std::string name;
  size_t count = 0;
  std::vector<PlyProperty> props;
  int stride = 0;
};

int ply_size(PlyType t) {
  static const int sizes[] = {1, 1, 2, 2, 4, 4, 4, 8};
  return sizes[int(t)];
}

bool ply_type(const std::string& s, PlyType& t) {
  static const std::pair<const char*, PlyType> names[] = {
      {"char", PlyType::I8},     {"int8", PlyType::I8},     {"uchar", PlyType::U8},
      {"uint8", PlyType::U8},    {"short", PlyType::I16},   {"int16", PlyType::I16},
      {"ushort", PlyType::U16},  {"uint16", PlyType::U16},  {"int", PlyType::I32},
      {"int32", PlyType::I32},   {"uint", PlyType::U32},    {"uint32", PlyType::U32},
      {"float", PlyType::F32},   {"float32", PlyType::F32}, {"double", PlyType::F64},
      {"float64", PlyType::F64}};
  for (auto& [name, type] : names)
    if (s == name) return t = type, true;
  return false;
}

template <typename T>
T load(const char* p, bool swap) {
  char b[sizeof(T)];
  std::memcpy(b, p, sizeof(T));
  if (swap) std::reverse(b, b + sizeof(T));
  T v;
  std::memcpy(&v, b, sizeof(T));
  return v;
}

double ply_value(const char* p, PlyType t, bool swap) {
  switch (t) {
    case PlyType::I8: return int8_t(*p);
    case PlyType::U8: return uint8_t(*p);
    case PlyType::I16: return load<int16_t>(p, swap);
    case PlyType::U16: return load<uint16_t>(p, swap);
    case PlyType::I32: return load<int32_t>(p, swap);
    case PlyType::U32: return load<uint32_t>(p, swap);
    case PlyType::F32: return load<float>(p, swap);
    case PlyType::F64: return load<double>(p, swap);
  }
  return 0;
}

bool is_class_name(const std::string& name) {
  std::string n = lower(name);
  return n == "class" || n == "classification" || n == "scalar_classification";
}

PointCloud read_ply(const std::string& path) {
  std::vector<char> buf = slurp(path);
  const std::string head(buf.data(), std::min<size_t>(buf.size(), 1 << 16));
  size_t end = head.find("end_header");
  if (head.compare(0, 3, "ply") != 0) throw InputError(path, "not a PLY file (no 'ply' magic)");
  if (end == std::string::npos) throw InputError(path, "truncated PLY file: no end_header");
  std::istringstream lines(head.substr(0, end));
  std::string line, format;
  std::vector<PlyElement> elements;
  while (std::getline(lines, line)) {
    std::istringstream ls(line);
    std::string key;
    ls >> key;
    if (key == "format") {
      ls >> format;
    } else if (key == "element") {
      PlyElement e;
      ls >> e.name >> e.count;
      elements.push_back(e);
    } else if (key == "property" && !elements.empty()) {
      PlyProperty prop;
      std::string type;
      ls >> type;
      if (type == "list") {
        std::string count_type, item_type;
        ls >> count_type >> item_type;
        prop.is_list = true;
      } else if (!ply_type(type, prop.type)) {
        throw InputError(path, "unknown PLY property type '" + type + "'");
      }
      ls >> prop.name;
      PlyElement& e = elements.back();
      prop.offset = e.stride;
      if (!prop.is_list) e.stride += ply_size(prop.type);
      e.props.push_back(prop);
    }
  }
  size_t data = end + std::strlen("end_header");
  while (data < buf.size() && buf[data] != '\n') ++data;
  ++data;
  const bool ascii = format == "ascii";
  const bool swap = format == "binary_big_endian";
  if (!ascii && !swap && format != "binary_little_endian")
    throw InputError(path, "unknown PLY format '" + format + "'");

  // Only the vertex element is read; fixed-size elements before it are skipped.
  size_t skip_lines = 0, skip_bytes = 0;
  const PlyElement* vertex = nullptr;
  for (const PlyElement& e : elements) {
    if (e.name == "vertex") {
      vertex = &e;
      break;
    }
    for (const PlyProperty& p : e.props)
      if (p.is_list && !ascii)
        throw InputError(path, "PLY element '" + e.name + "' with lists before the vertices");
    skip_lines += e.count;
    skip_bytes += e.count * size_t(e.stride);
  }
  if (!vertex) throw InputError(path, "PLY file has no vertex element");
  int ix = -1, iy = -1, iz = -1, ic = -1;
  for (size_t i = 0; i < vertex->props.size(); ++i) {
    const PlyProperty& p = vertex->props[i];
    if (p.is_list) {
      if (!ascii) throw InputError(path, "PLY vertex list properties are not supported");
      continue;
    }
    if (p.name == "x") ix = int(i);
    if (p.name == "y") iy = int(i);
    if (p.name == "z") iz = int(i);
    if (is_class_name(p.name)) ic = int(i);
  }
  if (ix < 0 || iy < 0 || iz < 0) throw InputError(path, "PLY vertices have no x, y, z properties");
  const size_t n = vertex->count;
  PointCloud cloud;
  cloud.source = path;
  cloud.points.resize(n);
  if (ic >= 0) cloud.classes.resize(n);
  const auto& props = vertex->props;

  if (!ascii) {
    size_t need = data + skip_bytes + n * size_t(vertex->stride);
    if (need > buf.size())
      throw InputError(path, "truncated PLY file: header promises " + std::to_string(n) +
                                 " vertices, the data holds fewer");
    const char* rec = buf.data() + data + skip_bytes;
    for (size_t i = 0; i < n; ++i, rec += vertex->stride) {
      double x = ply_value(rec + props[ix].offset, props[ix].type, swap);
      double y = ply_value(rec + props[iy].offset, props[iy].type, swap);
      double z = ply_value(rec + props[iz].offset, props[iz].type, swap);
      check_finite(path, x, y, z, i);
      cloud.points[i] = Vec3(x, y, z);
      if (ic >= 0) cloud.classes[i] = uint8_t(ply_value(rec + props[ic].offset, props[ic].type, swap));
    }
    return cloud;
  }
  const char* p = buf.data() + data;
  const char* stop = buf.data() + buf.size();
  auto next_line = [&]() {
    while (p < stop && *p != '\n') ++p;
    if (p < stop) ++p;
  };
  for (size_t i = 0; i < skip_lines; ++i) next_line();
  std::vector<double> v(props.size());
  for (size_t i = 0; i < n; ++i) {
    for (size_t k = 0; k < props.size(); ++k) {
      while (p < stop && (*p == ' ' || *p == '\t' || *p == '\r')) ++p;
      auto r = std::from_chars(p, stop, v[k]);
      if (r.ec != std::errc() && !props[k].is_list)
        throw InputError(path, "truncated or malformed PLY: vertex " + std::to_string(i) +
                                   " has no value for '" + props[k].name + "'");
      p = r.ptr;
      if (props[k].is_list) break;  // rest of the line is the list
    }
    check_finite(path, v[ix], v[iy], v[iz], i);
    cloud.points[i] = Vec3(v[ix], v[iy], v[iz]);
    if (ic >= 0) cloud.classes[i] = uint8_t(v[ic]);
    next_line();
  }
  return cloud;
}

// ---------------------------------------------------------------- PCD ----

PointCloud read_pcd(const std::string& path) {
  if (fs::exists(path) && fs::file_size(path) == 0) throw InputError(path, "empty file");
  pcl::PCLPointCloud2 blob;
  if (pcl::io::loadPCDFile(path, blob) < 0) throw InputError(path, "cannot read PCD file");
  const pcl::PCLPointField *fx = nullptr, *fy = nullptr, *fz = nullptr, *fc = nullptr;
  for (const auto& f : blob.fields) {
    if (f.name == "x") fx = &f;
    if (f.name == "y") fy = &f;
    if (f.name == "z") fz = &f;
    if (is_class_name(f.name) || f.name == "label") fc = &f;
  }
  if (!fx || !fy || !fz) throw InputError(path, "PCD has no x, y, z fields");
  auto value = [&](const uint8_t* rec, const pcl::PCLPointField* f) -> double {
    const char* q = reinterpret_cast<const char*>(rec + f->offset);
    switch (f->datatype) {
      case pcl::PCLPointField::INT8: return int8_t(*q);
      case pcl::PCLPointField::UINT8: return uint8_t(*q);
      case pcl::PCLPointField::INT16: return get<int16_t>(q);
      case pcl::PCLPointField::UINT16: return get<uint16_t>(q);
      case pcl::PCLPointField::INT32: return get<int32_t>(q);
      case pcl::PCLPointField::UINT32: return get<uint32_t>(q);
      case pcl::PCLPointField::FLOAT32: return get<float>(q);
      case pcl::PCLPointField::FLOAT64: return get<double>(q);
    }
    return kNaN;
  };
  size_t n = size_t(blob.width) * blob.height;
  PointCloud cloud;
  cloud.source = path;
  cloud.points.reserve(n);
  if (fc) cloud.classes.reserve(n);
  for (size_t i = 0; i < n; ++i) {
    const uint8_t* rec = blob.data.data() + i * blob.point_step;
    double x = value(rec, fx), y = value(rec, fy), z = value(rec, fz);
    check_finite(path, x, y, z, i);
    cloud.points.emplace_back(x, y, z);
    if (fc) cloud.classes.push_back(uint8_t(value(rec, fc)));
  }
  return cloud;
}

// ------------------------------------------------------------ XYZ/CSV ----

PointCloud read_xyz(const std::string& path) {
  std::vector<char> buf = slurp(path);
  PointCloud cloud;
  cloud.source = path;
  const char* p = buf.data();
  const char* stop = p + buf.size();
  int cx = 0, cy = 1, cz = 2, cc = 3;  // column indices; a header may rename them
  bool header_seen = false, first = true;
  size_t line_no = 0;
  std::vector<double> cols;
  while (p < stop) {
    const char* eol = static_cast<const char*>(std::memchr(p, '\n', size_t(stop - p)));
    if (!eol) eol = stop;
    ++line_no;
    std::string_view line(p, size_t(eol - p));
    p = eol + 1;
    size_t s = line.find_first_not_of(" \t\r");
    if (s == std::string_view::npos || line[s] == '#') continue;
    // Split on commas, semicolons and whitespace.
    cols.clear();
    bool numeric = true;
    std::vector<std::string> names;
    const char* q = line.data() + s;
    const char* e = line.data() + line.size();
    while (q < e) {
      while (q < e && (*q == ' ' || *q == '\t' || *q == '\r' || *q == ',' || *q == ';')) ++q;
      if (q >= e) break;
      const char* t = q;
      while (t < e && !(*t == ' ' || *t == '\t' || *t == '\r' || *t == ',' || *t == ';')) ++t;
      double v;
      auto r = std::from_chars(*q == '+' ? q + 1 : q, t, v);
      if (r.ec != std::errc() || r.ptr != t) numeric = false;
      if (first) names.push_back(lower(std::string(q, t)));
      cols.push_back(v);
      q = t;
    }
    if (first && !numeric && !header_seen) {  // header line: map named columns
      header_seen = true;
      cc = -1;
      for (size_t i = 0; i < names.size(); ++i) {
        std::string n = names[i];
        n.erase(std::remove(n.begin(), n.end(), '"'), n.end());
        if (n == "x" || n == "//x") cx = int(i);
        if (n == "y") cy = int(i);
        if (n == "z") cz = int(i);
        if (is_class_name(n) || n == "label") cc = int(i);
      }
      continue;
    }
    first = false;
    if (!numeric)
      throw InputError(path, "line " + std::to_string(line_no) + " is not numeric: '" +
                                 std::string(line.substr(0, 60)) + "'");
    int need = std::max({cx, cy, cz}) + 1;
    if (int(cols.size()) < need)
      throw InputError(path, "line " + std::to_string(line_no) + " has " +
                                 std::to_string(cols.size()) + " columns, x y z needed");
    double x = cols[cx], y = cols[cy], z = cols[cz];
    if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z))
      throw InputError(path, "NaN/inf coordinate at line " + std::to_string(line_no));
    cloud.points.emplace_back(x, y, z);
    if (cc >= 0 && int(cols.size()) > cc) {
      double c = cols[cc];
      if (!(c >= 0 && c <= 255 && c == std::floor(c)))
        throw InputError(path, "line " + std::to_string(line_no) + ": class column value " +
                                   std::to_string(c) + " is not a class code 0-255");
      if (cloud.classes.size() + 1 < cloud.points.size())
        throw InputError(path, "line " + std::to_string(line_no) +
                                   " has a class column, earlier lines do not");
      cloud.classes.push_back(uint8_t(c));
    } else if (!cloud.classes.empty()) {
      throw InputError(path, "line " + std::to_string(line_no) + " has no class column");
    }
  }
  if (cloud.points.empty()) throw InputError(path, "no points in the file");
  return cloud;
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

}  // namespace

PointCloud read_point_cloud(const std::string& path) {
  if (!fs::exists(path)) throw InputError(path, "file not found");
  std::string ext = extension(path);
  if (ext == ".laz")
    throw InputError(path, "LAZ is not supported; convert it to LAS first, e.g. "
                           "`pdal translate in.laz out.las` or `las2las -i in.laz -o out.las`");
  if (ext == ".las") return read_las(path);
  if (ext == ".ply") return read_ply(path);
  if (ext == ".pcd") return read_pcd(path);
  if (ext == ".xyz" || ext == ".txt" || ext == ".csv" || ext == ".pts") return read_xyz(path);
  throw InputError(path, "unknown point-cloud format '" + ext +
                             "' (read: .las .ply .pcd .xyz .txt .csv)");
}

void write_las(const std::string& path, const PointCloud& cloud, int point_format,
               int minor_version) {
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
  uint32_t legacy = extended ? 0 : uint32_t(n);
  put<uint32_t>(out, 107, legacy);
  put<uint32_t>(out, 111, legacy);  // all points are first returns
  for (int i = 0; i < 3; ++i) {
    put<double>(out, 131 + 8 * i, scale[i]);
    put<double>(out, 155 + 8 * i, offset[i]);
    put<double>(out, 179 + 16 * i, hi[i]);
    put<double>(out, 187 + 16 * i, lo[i]);
  }
  if (minor_version >= 4) {
    put<uint64_t>(out, 247, n);
    put<uint64_t>(out, 255, n);
  }
  std::memcpy(&out[header_size], vlr.data(), vlr.size());

  const bool has_classes = cloud.classes.size() == n;
  for (size_t i = 0; i < n; ++i) {
    size_t r = point_offset + i * record;
    const Vec3& p = cloud.points[i];
    for (int k = 0; k < 3; ++k)
      put<int32_t>(out, r + 4 * k, int32_t(std::llround((p[k] - offset[k]) / scale[k])));
    uint8_t cls = has_classes ? cloud.classes[i] : 1;  // 1 = unclassified
    if (extended) {
      out[r + 14] = char(0x11);  // return 1 of 1
      out[r + 16] = char(cls);
    } else {
      out[r + 14] = char(0x09);  // return 1 of 1
      out[r + 15] = char(cls & 0x1F);
    }
  }
  std::unique_ptr<FILE, int (*)(FILE*)> f(std::fopen(path.c_str(), "wb"), &std::fclose);
  if (!f || std::fwrite(out.data(), 1, out.size(), f.get()) != out.size())
    throw InputError(path, "cannot write LAS file");
}

}  // namespace c3d

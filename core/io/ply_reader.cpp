// The PLY reader: ASCII and binary (either byte order); only the vertex
// element is read, x y z and an optional class property.
#include <algorithm>
#include <charconv>
#include <cstring>
#include <sstream>

#include "core/error.h"
#include "core/io/point_io_detail.h"

namespace c3d {

using namespace point_io_detail;

namespace {

enum class PlyType { I8, U8, I16, U16, I32, U32, F32, F64 };

struct PlyProperty {
  std::string name;
  PlyType type = PlyType::U8;
  int offset = 0;  // byte offset within a binary vertex record
  bool is_list = false;
};

struct PlyElement {
  std::string name;
  size_t count = 0;
  std::vector<PlyProperty> props;
  int stride = 0;
};

struct PlyHeader {
  std::string format;
  std::vector<PlyElement> elements;
  size_t data = 0;  // byte offset of the first data line / record
};

// Where the vertices are and which of their properties hold x, y, z and the class.
struct PlyVertices {
  const PlyElement* vertex = nullptr;
  size_t skip_lines = 0, skip_bytes = 0;  // the elements before the vertices
  int ix = -1, iy = -1, iz = -1, ic = -1;
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

PlyProperty parse_property(const std::string& path, std::istringstream& ls) {
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
  return prop;
}

PlyHeader parse_ply_header(const std::string& path, const std::vector<char>& buf) {
  const std::string head(buf.data(), std::min<size_t>(buf.size(), 1 << 16));
  size_t end = head.find("end_header");
  if (head.compare(0, 3, "ply") != 0) throw InputError(path, "not a PLY file (no 'ply' magic)");
  if (end == std::string::npos) throw InputError(path, "truncated PLY file: no end_header");
  std::istringstream lines(head.substr(0, end));
  std::string line;
  PlyHeader h;
  while (std::getline(lines, line)) {
    std::istringstream ls(line);
    std::string key;
    ls >> key;
    if (key == "format") {
      ls >> h.format;
    } else if (key == "element") {
      PlyElement e;
      std::string count;
      ls >> e.name >> count;
      auto r = std::from_chars(count.data(), count.data() + count.size(), e.count);
      if (r.ec != std::errc() || r.ptr != count.data() + count.size())
        throw InputError(path, "PLY element '" + e.name + "' has no valid count ('" + count + "')");
      h.elements.push_back(e);
    } else if (key == "property" && !h.elements.empty()) {
      PlyProperty prop = parse_property(path, ls);
      PlyElement& e = h.elements.back();
      prop.offset = e.stride;
      if (!prop.is_list) e.stride += ply_size(prop.type);
      e.props.push_back(prop);
    }
  }
  h.data = end + std::strlen("end_header");
  while (h.data < buf.size() && buf[h.data] != '\n') ++h.data;
  h.data = std::min(h.data + 1, buf.size());
  return h;
}

// A header's count is checked against the bytes after the header before
// anything is allocated: an ASCII record takes at least one byte (its line
// end), a binary one its stride.
void check_claim(const std::string& path, const PlyElement& e, size_t record_bytes, size_t avail) {
  const size_t most = avail / std::max<size_t>(record_bytes, 1);
  if (e.count > most)
    throw InputError(path, "truncated PLY file: header claims " + std::to_string(e.count) + " '" + e.name +
                               "' records; the " + std::to_string(avail) +
                               " bytes after the header hold at most " + std::to_string(most));
}

PlyVertices find_vertices(const std::string& path, const PlyHeader& h, bool ascii, size_t avail) {
  // Only the vertex element is read; fixed-size elements before it are skipped.
  PlyVertices v;
  for (const PlyElement& e : h.elements) {
    const size_t record = ascii ? 1 : size_t(e.stride);
    if (e.name == "vertex") {
      v.vertex = &e;
      if (!ascii) avail -= v.skip_bytes;
      if (record > 0) check_claim(path, e, record, avail);
      break;
    }
    for (const PlyProperty& p : e.props)
      if (p.is_list && !ascii)
        throw InputError(path, "PLY element '" + e.name + "' with lists before the vertices");
    if (record == 0) continue;  // a binary element without properties takes no bytes
    check_claim(path, e, record, ascii ? avail : avail - v.skip_bytes);
    v.skip_lines += e.count;
    v.skip_bytes += e.count * record;
  }
  if (!v.vertex) throw InputError(path, "PLY file has no vertex element");
  for (size_t i = 0; i < v.vertex->props.size(); ++i) {
    const PlyProperty& p = v.vertex->props[i];
    if (p.is_list) {
      if (!ascii) throw InputError(path, "PLY vertex list properties are not supported");
      continue;
    }
    if (p.name == "x") v.ix = int(i);
    if (p.name == "y") v.iy = int(i);
    if (p.name == "z") v.iz = int(i);
    if (is_class_name(p.name)) v.ic = int(i);
  }
  if (v.ix < 0 || v.iy < 0 || v.iz < 0)
    throw InputError(path, "PLY vertices have no x, y, z properties");
  return v;
}

void read_ply_binary(const std::string& path, const std::vector<char>& buf, size_t data,
                     const PlyVertices& v, bool swap, PointCloud& cloud) {
  const size_t n = v.vertex->count;
  const auto& props = v.vertex->props;
  const int ix = v.ix, iy = v.iy, iz = v.iz, ic = v.ic;
  size_t need = data + v.skip_bytes + n * size_t(v.vertex->stride);
  if (need > buf.size())
    throw InputError(path, "truncated PLY file: header promises " + std::to_string(n) +
                               " vertices, the data holds fewer");
  const char* rec = buf.data() + data + v.skip_bytes;
  for (size_t i = 0; i < n; ++i, rec += v.vertex->stride) {
    double x = ply_value(rec + props[ix].offset, props[ix].type, swap);
    double y = ply_value(rec + props[iy].offset, props[iy].type, swap);
    double z = ply_value(rec + props[iz].offset, props[iz].type, swap);
    check_coordinates(path, x, y, z, i);
    cloud.points[i] = Vec3(x, y, z);
    if (ic >= 0)
      cloud.classes[i] = class_code(path, ply_value(rec + props[ic].offset, props[ic].type, swap), i);
  }
}

void read_ply_ascii(const std::string& path, const std::vector<char>& buf, size_t data,
                    const PlyVertices& vs, PointCloud& cloud) {
  const size_t n = vs.vertex->count;
  const auto& props = vs.vertex->props;
  const int ix = vs.ix, iy = vs.iy, iz = vs.iz, ic = vs.ic;
  const char* p = buf.data() + data;
  const char* stop = buf.data() + buf.size();
  auto next_line = [&]() {
    while (p < stop && *p != '\n') ++p;
    if (p < stop) ++p;
  };
  for (size_t i = 0; i < vs.skip_lines && p < stop; ++i) next_line();
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
    check_coordinates(path, v[ix], v[iy], v[iz], i);
    cloud.points[i] = Vec3(v[ix], v[iy], v[iz]);
    if (ic >= 0) cloud.classes[i] = class_code(path, v[ic], i);
    next_line();
  }
}

}  // namespace

PointCloud point_io_detail::read_ply(const std::string& path) {
  std::vector<char> buf = slurp(path);
  const PlyHeader h = parse_ply_header(path, buf);
  const bool ascii = h.format == "ascii";
  const bool swap = h.format == "binary_big_endian";
  if (!ascii && !swap && h.format != "binary_little_endian")
    throw InputError(path, "unknown PLY format '" + h.format + "'");
  const PlyVertices v = find_vertices(path, h, ascii, buf.size() - h.data);
  const size_t n = v.vertex->count;
  PointCloud cloud;
  cloud.source = path;
  cloud.points.resize(n);
  if (v.ic >= 0) cloud.classes.resize(n);
  if (ascii) read_ply_ascii(path, buf, h.data, v, cloud);
  else read_ply_binary(path, buf, h.data, v, swap, cloud);
  return cloud;
}

}  // namespace c3d

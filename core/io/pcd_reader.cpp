// The PCD reader (PCL's format, v0.5-0.7): ascii, binary and binary_compressed
// (LZF). Its own code rather than pcl::io::loadPCDFile, which crashed on a
// header line out of place (found by tests/fuzz): every count and size here is
// checked against the file before it is trusted.
#include <algorithm>
#include <array>
#include <charconv>
#include <cstring>
#include <sstream>

#include "core/error.h"
#include "core/io/point_io_detail.h"

namespace c3d {

using namespace point_io_detail;

namespace {

// LZF packs at most 264 bytes into a 3-byte back reference, so no valid
// stream expands more than about 88 times; a larger claim is damage.
constexpr uint64_t kMaxLzfExpansion = 96;

struct PcdField {
  std::string name;
  int size = 4;     // bytes of one element
  char type = 'F';  // I, U or F
  uint64_t count = 1;
  size_t offset = 0;  // within a point record (binary) or a column index (ascii)
};

struct PcdHeader {
  std::vector<PcdField> fields;
  uint64_t width = 0, height = 1, points = 0;
  bool has_points = false;
  std::string data;     // ascii, binary or binary_compressed
  size_t body = 0;      // offset of the data after the DATA line
  size_t point_step = 0;
};

std::vector<std::string> words(const std::string& line) {
  std::istringstream s(line);
  std::vector<std::string> out;
  for (std::string w; s >> w;) out.push_back(w);
  return out;
}

uint64_t parse_count(const std::string& path, const std::string& key, const std::string& text) {
  uint64_t v = 0;
  auto r = std::from_chars(text.data(), text.data() + text.size(), v);
  if (r.ec != std::errc() || r.ptr != text.data() + text.size())
    throw InputError(path, "PCD " + key + " '" + text + "' is not a whole number");
  return v;
}

// SIZE, TYPE and COUNT give one value per field.
void set_per_field(const std::string& path, PcdHeader& h, const std::vector<std::string>& w) {
  if (w.size() != h.fields.size() + 1)
    throw InputError(path, "PCD " + w[0] + " has " + std::to_string(w.size() - 1) + " values for " +
                               std::to_string(h.fields.size()) + " fields (FIELDS must come first)");
  for (size_t i = 0; i < h.fields.size(); ++i) {
    PcdField& f = h.fields[i];
    if (w[0] == "SIZE") f.size = int(parse_count(path, "SIZE", w[i + 1]));
    if (w[0] == "TYPE") f.type = w[i + 1].size() == 1 ? w[i + 1][0] : '?';
    if (w[0] == "COUNT") f.count = parse_count(path, "COUNT", w[i + 1]);
  }
}

void check_fields(const std::string& path, PcdHeader& h) {
  if (h.fields.empty()) throw InputError(path, "PCD header has no FIELDS");
  size_t step = 0;
  for (PcdField& f : h.fields) {
    const bool ok = (f.type == 'F' && (f.size == 4 || f.size == 8)) ||
                    ((f.type == 'I' || f.type == 'U') && (f.size == 1 || f.size == 2 || f.size == 4 || f.size == 8));
    if (!ok)
      throw InputError(path, "PCD field '" + f.name + "' has TYPE " + std::string(1, f.type) + " SIZE " +
                                 std::to_string(f.size) + " (F 4/8, I or U 1/2/4/8 are read)");
    if (f.count < 1 || f.count > 1024)  // 1024: more elements than any PCL point type holds
      throw InputError(path, "PCD field '" + f.name + "' has COUNT " + std::to_string(f.count));
    f.offset = step;
    step += size_t(f.size) * f.count;
  }
  h.point_step = step;
}

PcdHeader parse_pcd_header(const std::string& path, const std::vector<char>& buf) {
  PcdHeader h;
  size_t pos = 0;
  while (pos < buf.size() && h.data.empty()) {
    const char* eol = static_cast<const char*>(std::memchr(buf.data() + pos, '\n', buf.size() - pos));
    const size_t end = eol ? size_t(eol - buf.data()) : buf.size();
    const std::vector<std::string> w = words(std::string(buf.data() + pos, end - pos));
    pos = std::min(end + 1, buf.size());
    if (w.empty() || w[0][0] == '#' || w[0] == "VERSION" || w[0] == "VIEWPOINT") continue;
    if (w[0] == "FIELDS" || w[0] == "COLUMNS") {  // COLUMNS: PCD v0.5
      h.fields.clear();
      for (size_t i = 1; i < w.size(); ++i) h.fields.push_back({w[i]});
    } else if (w[0] == "SIZE" || w[0] == "TYPE" || w[0] == "COUNT") {
      set_per_field(path, h, w);
    } else if ((w[0] == "WIDTH" || w[0] == "HEIGHT" || w[0] == "POINTS") && w.size() == 2) {
      uint64_t v = parse_count(path, w[0], w[1]);
      if (w[0] == "WIDTH") h.width = v;
      if (w[0] == "HEIGHT") h.height = v;
      if (w[0] == "POINTS") h.points = v, h.has_points = true;
    } else if (w[0] == "DATA" && w.size() == 2) {
      h.data = w[1];
    } else {
      throw InputError(path, "PCD header line '" + w[0] + "' is not understood (data before DATA?)");
    }
  }
  if (h.data != "ascii" && h.data != "binary" && h.data != "binary_compressed")
    throw InputError(path, h.data.empty() ? "PCD header has no DATA line" : "unknown PCD DATA '" + h.data + "'");
  check_fields(path, h);
  if (h.height != 0 && h.width > UINT64_MAX / h.height)
    throw InputError(path, "PCD WIDTH x HEIGHT overflows");
  if (!h.has_points) h.points = h.width * h.height;
  if (h.points != h.width * h.height)
    throw InputError(path, "PCD POINTS " + std::to_string(h.points) + " is not WIDTH x HEIGHT " +
                               std::to_string(h.width) + " x " + std::to_string(h.height));
  h.body = pos;
  return h;
}

// Checked LZF (liblzf's format): literal runs and back references, every
// read and write within its buffer; false on any inconsistency.
bool lzf_decompress(const uint8_t* in, size_t in_len, uint8_t* out, size_t out_len) {
  size_t ip = 0, op = 0;
  while (ip < in_len) {
    size_t ctrl = in[ip++];
    if (ctrl < 32) {  // literal run of ctrl + 1 bytes
      const size_t len = ctrl + 1;
      if (len > in_len - ip || len > out_len - op) return false;
      std::memcpy(out + op, in + ip, len);
      ip += len, op += len;
      continue;
    }
    size_t len = ctrl >> 5;
    if (len == 7) {
      if (ip >= in_len) return false;
      len += in[ip++];
    }
    if (ip >= in_len) return false;
    const size_t back = ((ctrl & 0x1f) << 8) + in[ip++] + 1;
    len += 2;
    if (back > op || len > out_len - op) return false;
    for (size_t k = 0; k < len; ++k, ++op) out[op] = out[op - back];  // may overlap
  }
  return op == out_len;
}

// binary_compressed holds the fields one after another (all x, then all y...);
// returns the records in the binary (interleaved) layout.
std::vector<uint8_t> decompress_body(const std::string& path, const std::vector<char>& buf, const PcdHeader& h) {
  if (buf.size() - h.body < 8) throw InputError(path, "truncated PCD file: no compressed sizes");
  uint32_t packed = 0, unpacked = 0;
  std::memcpy(&packed, buf.data() + h.body, 4);
  std::memcpy(&unpacked, buf.data() + h.body + 4, 4);
  const uint64_t expected = h.points * h.point_step;
  if (packed > buf.size() - h.body - 8 || unpacked != expected ||
      uint64_t(unpacked) > kMaxLzfExpansion * uint64_t(packed) + 64)
    throw InputError(path, "PCD compressed sizes (" + std::to_string(packed) + " -> " + std::to_string(unpacked) +
                               " bytes) do not fit the file or the header's " + std::to_string(h.points) +
                               " points of " + std::to_string(h.point_step) + " bytes");
  std::vector<uint8_t> soa(unpacked), records(unpacked);
  const auto* in = reinterpret_cast<const uint8_t*>(buf.data() + h.body + 8);
  if (unpacked && !lzf_decompress(in, packed, soa.data(), soa.size()))
    throw InputError(path, "PCD compressed data is damaged (LZF)");
  size_t from = 0;
  for (const PcdField& f : h.fields) {
    const size_t bytes = size_t(f.size) * f.count;
    for (uint64_t i = 0; i < h.points; ++i, from += bytes)
      std::memcpy(&records[i * h.point_step + f.offset], &soa[from], bytes);
  }
  return records;
}

double element(const uint8_t* p, const PcdField& f) {
  switch (f.type == 'F' ? f.size : f.type == 'I' ? -f.size : 10 + f.size) {
    case 4: return get<float>(reinterpret_cast<const char*>(p));
    case 8: return get<double>(reinterpret_cast<const char*>(p));
    case -1: return int8_t(*p);
    case -2: return get<int16_t>(reinterpret_cast<const char*>(p));
    case -4: return get<int32_t>(reinterpret_cast<const char*>(p));
    case -8: return double(get<int64_t>(reinterpret_cast<const char*>(p)));
    case 11: return *p;
    case 12: return get<uint16_t>(reinterpret_cast<const char*>(p));
    case 14: return get<uint32_t>(reinterpret_cast<const char*>(p));
    default: return double(get<uint64_t>(reinterpret_cast<const char*>(p)));
  }
}

// Which fields hold x, y, z and the class; -1 for the class when none does.
std::array<int, 4> xyz_class(const std::string& path, const PcdHeader& h) {
  std::array<int, 4> at{-1, -1, -1, -1};
  for (size_t i = 0; i < h.fields.size(); ++i) {
    const std::string& n = h.fields[i].name;
    if (n == "x") at[0] = int(i);
    if (n == "y") at[1] = int(i);
    if (n == "z") at[2] = int(i);
    if (is_class_name(n) || n == "label") at[3] = int(i);
  }
  if (at[0] < 0 || at[1] < 0 || at[2] < 0) throw InputError(path, "PCD has no x, y, z fields");
  return at;
}

void read_records(const std::string& path, const uint8_t* data, const PcdHeader& h, PointCloud& cloud) {
  const std::array<int, 4> at = xyz_class(path, h);
  const PcdField *fx = &h.fields[at[0]], *fy = &h.fields[at[1]], *fz = &h.fields[at[2]];
  const PcdField* fc = at[3] >= 0 ? &h.fields[at[3]] : nullptr;
  for (uint64_t i = 0; i < h.points; ++i) {
    const uint8_t* rec = data + i * h.point_step;
    const double x = element(rec + fx->offset, *fx), y = element(rec + fy->offset, *fy),
                 z = element(rec + fz->offset, *fz);
    check_coordinates(path, x, y, z, i);
    cloud.points.emplace_back(x, y, z);
    if (fc) cloud.classes.push_back(class_code(path, element(rec + fc->offset, *fc), i));
  }
}

// ascii: one point per line, every element of every field in order.
void read_ascii(const std::string& path, const std::vector<char>& buf, const PcdHeader& h, PointCloud& cloud) {
  const std::array<int, 4> at = xyz_class(path, h);
  std::vector<size_t> column(h.fields.size());
  size_t columns = 0;
  for (size_t i = 0; i < h.fields.size(); ++i) column[i] = columns, columns += h.fields[i].count;
  std::vector<double> v(columns);
  const char* p = buf.data() + h.body;
  const char* stop = buf.data() + buf.size();
  for (uint64_t i = 0; i < h.points; ++i) {
    for (size_t k = 0; k < columns; ++k) {
      while (p < stop && (*p == ' ' || *p == '\t' || *p == '\r' || *p == '\n')) ++p;
      auto r = std::from_chars(p, stop, v[k]);
      if (r.ec != std::errc())
        throw InputError(path, "truncated or malformed PCD: point " + std::to_string(i) + " has " +
                                   std::to_string(k) + " of " + std::to_string(columns) + " values");
      p = r.ptr;
    }
    const double x = v[column[at[0]]], y = v[column[at[1]]], z = v[column[at[2]]];
    check_coordinates(path, x, y, z, i);
    cloud.points.emplace_back(x, y, z);
    if (at[3] >= 0) cloud.classes.push_back(class_code(path, v[column[at[3]]], i));
  }
}

}  // namespace

PointCloud point_io_detail::read_pcd(const std::string& path) {
  std::vector<char> buf = slurp(path);
  const PcdHeader h = parse_pcd_header(path, buf);
  // Every claim against the bytes after the header, before allocating: an
  // ascii point takes at least one byte per value, a binary one its record.
  const uint64_t avail = buf.size() - h.body;
  const uint64_t most = h.data == "ascii" ? avail : h.data == "binary" ? avail / h.point_step
                                                  : (kMaxLzfExpansion * avail + 64) / h.point_step;
  if (h.points > most)
    throw InputError(path, "PCD header claims " + std::to_string(h.points) + " points; the " +
                               std::to_string(avail) + " bytes of " + h.data + " data hold at most " +
                               std::to_string(most));
  PointCloud cloud;
  cloud.source = path;
  cloud.points.reserve(h.points);
  if (h.data == "ascii") {
    read_ascii(path, buf, h, cloud);
  } else if (h.data == "binary") {
    read_records(path, reinterpret_cast<const uint8_t*>(buf.data() + h.body), h, cloud);
  } else {
    const std::vector<uint8_t> records = decompress_body(path, buf, h);
    read_records(path, records.data(), h, cloud);
  }
  return cloud;
}

}  // namespace c3d

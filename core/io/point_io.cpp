// Point-cloud readers (own LAS 1.0-1.4, PLY, PCD and XYZ/CSV readers) and the
// LAS writer. Files are read with one bulk fread and parsed from memory. LAS
// reading and writing are in las_io.cpp, PLY in ply_reader.cpp, PCD in
// pcd_reader.cpp.
#include "core/io/point_io.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>

#include "core/error.h"
#include "core/io/point_io_detail.h"
#include "core/io/read_limits.h"

namespace c3d {

using namespace point_io_detail;

std::string point_io_detail::lower(std::string s) {
  for (char& c : s) c = char(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// A directory named x.las opened fine and reported a size of 2^63 (ext4), which
// became std::bad_alloc: only a regular file is read, its size checked.
std::vector<char> point_io_detail::slurp(const std::string& path) {
  check_regular_file(path);
  std::unique_ptr<FILE, int (*)(FILE*)> f(std::fopen(path.c_str(), "rb"), &std::fclose);
  if (!f) throw InputError(path, "cannot open file (" + std::string(std::strerror(errno)) + ")");
  std::fseek(f.get(), 0, SEEK_END);
  long size = std::ftell(f.get());
  std::fseek(f.get(), 0, SEEK_SET);
  if (size == 0) throw InputError(path, "empty file");
  if (size < 0) throw InputError(path, "cannot tell the file's size (" + std::string(std::strerror(errno)) + ")");
  std::vector<char> buf(static_cast<size_t>(size));
  if (std::fread(buf.data(), 1, buf.size(), f.get()) != buf.size())
    throw InputError(path, "read error");
  return buf;
}

void point_io_detail::check_coordinates(const std::string& path, double x, double y, double z,
                                        size_t index) {
  if (coordinate_ok(x) && coordinate_ok(y) && coordinate_ok(z)) return;
  throw InputError(path, coordinate_problem(x, y, z, "point " + std::to_string(index)));
}

uint8_t point_io_detail::class_code(const std::string& path, double c, size_t index) {
  if (!(c >= 0 && c <= 255 && c == std::floor(c)))
    throw InputError(path, "point " + std::to_string(index) + ": class value " + std::to_string(c) +
                               " is not a class code 0-255");
  return uint8_t(c);
}

bool point_io_detail::is_class_name(const std::string& name) {
  std::string n = lower(name);
  return n == "class" || n == "classification" || n == "scalar_classification";
}

namespace {

namespace fs = std::filesystem;

std::string extension(const std::string& path) { return lower(fs::path(path).extension().string()); }

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
    if (!coordinate_ok(x) || !coordinate_ok(y) || !coordinate_ok(z))
      throw InputError(path, coordinate_problem(x, y, z, "line " + std::to_string(line_no)));
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

}  // namespace

PointCloud read_point_cloud(const std::string& path) {
  check_regular_file(path);
  std::string ext = extension(path);
  if (ext == ".las" || ext == ".laz") return read_las(path);  // LAZ by its LASzip VLR
  if (ext == ".ply") return read_ply(path);
  if (ext == ".pcd") return read_pcd(path);
  if (ext == ".xyz" || ext == ".txt" || ext == ".csv" || ext == ".pts") return read_xyz(path);
  throw InputError(path, "unknown point-cloud format '" + ext +
                             "' (read: .las .laz .ply .pcd .xyz .txt .csv)");
}

namespace {

constexpr size_t kPointBlock = size_t(1) << 20;  // points per block: 25 MB, long enough to stream fast

bool is_las(const std::string& path) {
  const std::string ext = extension(path);
  return ext == ".las" || ext == ".laz";
}

}  // namespace

void for_each_point_block(const std::string& path, const std::function<void(const PointCloud&)>& block) {
  if (is_las(path)) return stream_las(path, kPointBlock, block);
  PointCloud whole = read_point_cloud(path);
  PointCloud part;
  part.source = whole.source;
  part.crs_wkt = whole.crs_wkt;
  for (size_t at = 0; at < whole.points.size(); at += kPointBlock) {
    const size_t end = std::min(whole.points.size(), at + kPointBlock);
    part.points.assign(whole.points.begin() + long(at), whole.points.begin() + long(end));
    if (!whole.classes.empty()) part.classes.assign(whole.classes.begin() + long(at), whole.classes.begin() + long(end));
    if (!whole.returns.empty()) part.returns.assign(whole.returns.begin() + long(at), whole.returns.begin() + long(end));
    block(part);
  }
}

CloudExtent decoded_cloud_extent(const std::string& path) {
  CloudExtent e;
  e.min_x = e.min_y = 1e300, e.max_x = e.max_y = -1e300;
  for_each_point_block(path, [&](const PointCloud& c) {
    e.crs_wkt = c.crs_wkt;
    e.points += c.points.size();
    for (const Vec3& p : c.points) {
      e.min_x = std::min(e.min_x, p.x()), e.max_x = std::max(e.max_x, p.x());
      e.min_y = std::min(e.min_y, p.y()), e.max_y = std::max(e.max_y, p.y());
    }
  });
  if (e.points == 0) e.min_x = e.min_y = e.max_x = e.max_y = 0;
  return e;
}

CloudExtent read_cloud_extent(const std::string& path) {
  check_regular_file(path);
  std::string note;
  if (is_las(path))
    if (auto e = las_header_extent(path)) {
      e->from_header = e->note.empty();
      if (e->from_header) return *e;
      note = e->note;
    }
  CloudExtent e = decoded_cloud_extent(path);
  e.note = note;
  return e;
}

}  // namespace c3d

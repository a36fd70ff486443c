#include "core/io/mesh_io.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>

#include "core/error.h"
#include "core/check/solid_check.h"
#include "core/io/read_limits.h"

namespace c3d {

std::string lower_ext(const std::string& path) {
  auto dot = path.find_last_of('.');
  std::string e = dot == std::string::npos ? "" : path.substr(dot + 1);
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return std::tolower(c); });
  return e;
}

namespace {

// ---- OBJ ---------------------------------------------------------------------

// Cadastre3D OBJ files are local: "# ... world = local + (x, y, z) ..." gives the
// offset, which vertices after the comment get added.
void read_offset_comment(const std::string& line, Vec3& offset) {
  const auto at = line.find("world = ");
  if (at == std::string::npos) return;
  const auto open = line.find("+ (", at);
  if (open == std::string::npos) return;
  double x, y, z;
  if (std::sscanf(line.c_str() + open + 3, "%lf, %lf, %lf", &x, &y, &z) == 3) offset = Vec3(x, y, z);
}

std::vector<MeshGroup> read_obj(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path, "cannot open");
  std::vector<Vec3> v;
  std::vector<MeshGroup> groups;
  std::string name, material, line;
  Vec3 offset = Vec3::Zero();
  long line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    std::istringstream s(line);
    std::string tag;
    if (!(s >> tag)) continue;
    if (tag[0] == '#') {
      read_offset_comment(line, offset);
    } else if (tag == "v") {
      double x, y, z;
      if (!(s >> x >> y >> z)) throw InputError(path, "line " + std::to_string(line_no) + ": bad vertex");
      const Vec3 p = Vec3(x, y, z) + offset;
      const std::string problem = coordinate_problem(p.x(), p.y(), p.z(), "line " + std::to_string(line_no));
      if (!problem.empty()) throw InputError(path, problem);
      v.push_back(p);
    } else if (tag == "g" || tag == "o") {
      std::getline(s >> std::ws, name);
    } else if (tag == "usemtl") {
      std::getline(s >> std::ws, material);
    } else if (tag == "f") {
      Face f;
      std::string tok;
      while (s >> tok) {
        long i = std::strtol(tok.c_str(), nullptr, 10);  // "i", "i/t", "i//n", "i/t/n"
        if (i < 0) i += long(v.size()) + 1;                // relative index
        if (i < 1 || i > long(v.size()))
          throw InputError(path, "line " + std::to_string(line_no) + ": vertex index out of range");
        f.ring.push_back(v[size_t(i - 1)]);
      }
      if (groups.empty() || groups.back().name != name || groups.back().material != material)
        groups.push_back({name, material, {}});
      groups.back().faces.push_back(std::move(f));
    }
  }
  return groups;
}

// ---- PLY ---------------------------------------------------------------------

struct PlyProperty {
  std::string name, type, count_type;  // count_type non-empty for lists
};
struct PlyElement {
  std::string name;
  long count = 0;
  std::vector<PlyProperty> props;
};

// A face's vertex list: longer than any polygon a model holds, and the
// count must be a whole number (a float count of 1e300 is damage).
constexpr double kMaxPlyListLength = 1 << 20;

int type_size(const std::string& t) {
  if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
  if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
  if (t == "int" || t == "uint" || t == "float" || t == "int32" || t == "uint32" || t == "float32") return 4;
  if (t == "double" || t == "float64") return 8;
  return 0;
}

class PlyValueReader {
 public:
  PlyValueReader(std::istream& in, const std::string& format) : in_(in), format_(format) {}
  double read(const std::string& type) {
    if (format_ == "ascii") {
      double x;
      if (!(in_ >> x)) throw std::runtime_error("truncated data");
      return x;
    }
    unsigned char b[8];
    const int n = type_size(type);
    if (!in_.read(reinterpret_cast<char*>(b), n)) throw std::runtime_error("truncated data");
    if (format_ == "binary_big_endian") std::reverse(b, b + n);
    auto as = [&](auto tag) {
      decltype(tag) x;
      std::memcpy(&x, b, sizeof x);
      return double(x);
    };
    if (type == "char" || type == "int8") return as(std::int8_t{});
    if (type == "uchar" || type == "uint8") return as(std::uint8_t{});
    if (type == "short" || type == "int16") return as(std::int16_t{});
    if (type == "ushort" || type == "uint16") return as(std::uint16_t{});
    if (type == "int" || type == "int32") return as(std::int32_t{});
    if (type == "uint" || type == "uint32") return as(std::uint32_t{});
    if (type == "float" || type == "float32") return as(float{});
    return as(double{});
  }

 private:
  std::istream& in_;
  std::string format_;
};

std::vector<MeshGroup> read_ply(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "cannot open");
  std::string line, format;
  std::vector<PlyElement> elements;
  std::getline(in, line);
  if (line.rfind("ply", 0) != 0) throw InputError(path, "not a PLY file");
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream s(line);
    std::string tag;
    s >> tag;
    if (tag == "format") s >> format;
    else if (tag == "element") {
      elements.push_back({});
      s >> elements.back().name >> elements.back().count;
    } else if (tag == "property" && !elements.empty()) {
      PlyProperty p;
      s >> p.type;
      if (p.type == "list") s >> p.count_type >> p.type;
      s >> p.name;
      if (type_size(p.type) == 0 || (!p.count_type.empty() && type_size(p.count_type) == 0))
        throw InputError(path, "unknown property type in '" + line + "'");
      elements.back().props.push_back(p);
    } else if (tag == "end_header") break;
  }
  if (format != "ascii" && format != "binary_little_endian" && format != "binary_big_endian")
    throw InputError(path, "unknown PLY format '" + format + "'");

  std::vector<Vec3> v;
  MeshGroup g;
  PlyValueReader r(in, format);
  try {
    for (const auto& e : elements) {
      if (e.props.empty()) continue;  // records of no bytes: a huge count must not spin
      for (long k = 0; k < e.count; ++k) {
        Vec3 p = Vec3::Zero();
        Face f;
        for (const auto& prop : e.props) {
          if (prop.count_type.empty()) {
            double x = r.read(prop.type);
            if (e.name == "vertex" && prop.name.size() == 1 && prop.name[0] >= 'x' && prop.name[0] <= 'z')
              p[prop.name[0] - 'x'] = x;
            continue;
          }
          const double count = r.read(prop.count_type);
          if (!(count >= 0 && count <= kMaxPlyListLength)) throw std::runtime_error("bad list length");
          for (long j = 0; j < long(count); ++j) {
            const double idx = r.read(prop.type);
            if (e.name != "face" || (prop.name != "vertex_indices" && prop.name != "vertex_index")) continue;
            if (!(idx >= 0 && idx < double(v.size()))) throw std::runtime_error("vertex index out of range");
            f.ring.push_back(v[size_t(idx)]);
          }
        }
        if (e.name == "vertex") {
          const std::string problem = coordinate_problem(p.x(), p.y(), p.z(), "vertex " + std::to_string(k));
          if (!problem.empty()) throw std::runtime_error(problem);
          v.push_back(p);
        }
        else if (e.name == "face") g.faces.push_back(std::move(f));
      }
    }
  } catch (const std::runtime_error& err) {
    throw InputError(path, err.what());
  }
  return {g};
}

// Writes a polygon, emitting each distinct vertex once per file (shared vertices
// keep the mesh connected for tools that check closedness).
class ObjWriter {
 public:
  ObjWriter(std::ostream& out, const Vec3& offset) : out_(out), offset_(offset) {}
  void polygon(const Ring3& ring) {
    std::vector<long> ids;
    for (const auto& p : ring) {
      auto [it, fresh] = index_.try_emplace({p.x(), p.y(), p.z()}, long(index_.size()) + 1);
      if (fresh) {
        const Vec3 q = p - offset_;
        out_ << "v " << q.x() << ' ' << q.y() << ' ' << q.z() << '\n';
      }
      ids.push_back(it->second);
    }
    out_ << 'f';
    for (long i : ids) out_ << ' ' << i;
    out_ << '\n';
  }

 private:
  std::ostream& out_;
  Vec3 offset_;
  std::map<std::array<double, 3>, long> index_;
};

}  // namespace

std::vector<MeshGroup> read_mesh_groups(const std::string& path) {
  check_regular_file(path);
  const std::string ext = lower_ext(path);
  if (ext == "obj") return read_obj(path);
  if (ext == "ply") return read_ply(path);
  throw InputError(path, "unknown mesh format (expected .obj or .ply)");
}

std::vector<Face> read_mesh_faces(const std::string& path) {
  std::vector<Face> out;
  for (auto& g : read_mesh_groups(path))
    for (auto& f : g.faces) out.push_back(std::move(f));
  return out;
}

void write_obj(const std::string& path, const std::vector<MeshGroup>& groups, const Vec3& offset) {
  std::ofstream out(path);
  if (!out) throw InputError(path, "cannot write");
  out.setf(std::ios::fixed);
  out.precision(6);
  out << "# cadastre3d " << C3D_VERSION << "\n";
  if (offset != Vec3::Zero())
    out << "# coordinates local: world = local + (" << offset.x() << ", " << offset.y() << ", " << offset.z()
        << ")\n";
  ObjWriter w(out, offset);
  for (const auto& g : groups) {
    out << "g " << (g.name.empty() ? "default" : g.name) << '\n';
    if (!g.material.empty()) out << "usemtl " << g.material << '\n';
    for (const auto& f : g.faces) {
      if (f.holes.empty()) {
        w.polygon(f.ring);
        continue;
      }
      for (const auto& t : triangulate(f)) w.polygon({t.a, t.b, t.c});
    }
  }
  if (!out) throw InputError(path, "write failed");
}

}  // namespace c3d

#include "core/mesh/glb.h"

#include <cstdint>
#include <cstring>
#include <fstream>

#include <nlohmann/json.hpp>

#include "core/error.h"

namespace c3d {

namespace {

constexpr uint32_t kMagic = 0x46546C67, kVersion = 2, kJsonChunk = 0x4E4F534A, kBinChunk = 0x004E4942;
using namespace gltf;

template <typename T>
void append(std::vector<unsigned char>& out, T v) {
  unsigned char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  out.insert(out.end(), b, b + sizeof(T));
}

void pad(std::vector<unsigned char>& bytes, unsigned char with) {
  while (bytes.size() % 4) bytes.push_back(with);
}

// Positions then indices; min and max of the positions as stored (float).
std::vector<unsigned char> binary_chunk(const TriMesh& mesh, std::vector<float>& lo, std::vector<float>& hi) {
  std::vector<unsigned char> bin;
  lo.assign(3, INFINITY), hi.assign(3, -INFINITY);
  for (const Vec3& v : mesh.vertices)
    for (int k = 0; k < 3; ++k) {
      const float f = float(v[k]);
      append(bin, f);
      lo[size_t(k)] = std::min(lo[size_t(k)], f), hi[size_t(k)] = std::max(hi[size_t(k)], f);
    }
  for (const auto& t : mesh.triangles)
    for (int i : t) append(bin, uint32_t(i));
  return bin;
}

nlohmann::json gltf_json(const TriMesh& mesh, const Vec3& offset, const std::string& name, size_t bin_bytes,
                         const std::vector<float>& lo, const std::vector<float>& hi) {
  const size_t positions = 12 * mesh.vertices.size(), indices = 12 * mesh.triangles.size();
  const double half = std::sqrt(0.5);
  return {
      {"asset", {{"version", "2.0"}, {"generator", "cadastre3d"}}},
      {"scene", 0},
      {"scenes", {{{"nodes", {0}}, {"extras", {{"world_offset", {offset.x(), offset.y(), offset.z()}}, {"up", "+Z"}}}}}},
      {"nodes", {{{"mesh", 0}, {"name", name}, {"rotation", {-half, 0.0, 0.0, half}}}}},  // +Z up onto glTF's +Y
      {"meshes", {{{"name", name}, {"primitives", {{{"attributes", {{"POSITION", 0}}}, {"indices", 1}, {"mode", kTriangles}}}}}}},
      {"buffers", {{{"byteLength", bin_bytes}}}},
      {"bufferViews",
       {{{"buffer", 0}, {"byteOffset", 0}, {"byteLength", positions}, {"target", kArrayBuffer}},
        {{"buffer", 0}, {"byteOffset", positions}, {"byteLength", indices}, {"target", kElementArrayBuffer}}}},
      {"accessors",
       {{{"bufferView", 0}, {"componentType", kFloat}, {"count", mesh.vertices.size()}, {"type", "VEC3"}, {"min", lo}, {"max", hi}},
        {{"bufferView", 1}, {"componentType", kUnsignedInt}, {"count", 3 * mesh.triangles.size()}, {"type", "SCALAR"}}}},
  };
}

}  // namespace

std::vector<unsigned char> glb_container(const std::string& text, std::vector<unsigned char> bin) {
  std::vector<unsigned char> json(text.begin(), text.end());
  pad(json, ' ');
  pad(bin, 0);
  std::vector<unsigned char> out;
  append(out, kMagic), append(out, kVersion), append(out, uint32_t(12 + 8 + json.size() + 8 + bin.size()));
  append(out, uint32_t(json.size())), append(out, kJsonChunk);
  out.insert(out.end(), json.begin(), json.end());
  append(out, uint32_t(bin.size())), append(out, kBinChunk);
  out.insert(out.end(), bin.begin(), bin.end());
  return out;
}

std::vector<unsigned char> glb_bytes(const TriMesh& mesh, const Vec3& offset, const std::string& name) {
  std::vector<float> lo, hi;
  std::vector<unsigned char> bin = binary_chunk(mesh, lo, hi);
  const std::string text = gltf_json(mesh, offset, name, bin.size(), lo, hi).dump();  // before bin moves
  return glb_container(text, std::move(bin));
}

void write_glb(const std::string& path, const TriMesh& mesh, const Vec3& offset, const std::string& name) {
  const std::vector<unsigned char> bytes = glb_bytes(mesh, offset, name);
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
  if (!out) throw InputError(path, "cannot be written");
}

}  // namespace c3d

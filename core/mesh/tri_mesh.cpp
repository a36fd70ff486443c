#include "core/mesh/tri_mesh.h"

namespace c3d {

TriMesh without_loose_vertices(const TriMesh& mesh) {
  std::vector<int> index(mesh.vertices.size(), -1);
  TriMesh out;
  out.triangles.reserve(mesh.triangles.size());
  for (const auto& t : mesh.triangles) {
    std::array<int, 3> renumbered{};
    for (size_t k = 0; k < 3; ++k) {
      int& i = index[size_t(t[k])];
      if (i < 0) i = int(out.vertices.size()), out.vertices.push_back(mesh.vertices[size_t(t[k])]);
      renumbered[k] = i;
    }
    out.triangles.push_back(renumbered);
  }
  return out;
}

}  // namespace c3d

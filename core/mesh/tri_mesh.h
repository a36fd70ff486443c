#pragma once
// A triangle mesh as plain data: vertices and index triples, in the frame the
// caller works in (a building's local origin). The mesh ladder (core/mesh)
// and the optimizer (core/optimizer) pass it between stages.
#include <array>
#include <vector>

#include "core/types.h"

namespace c3d {

struct TriMesh {
  std::vector<Vec3> vertices;
  std::vector<std::array<int, 3>> triangles;
  std::vector<std::array<Vec3, 3>> soup() const {  // each triangle's corners
    std::vector<std::array<Vec3, 3>> out;
    out.reserve(triangles.size());
    for (const auto& t : triangles) out.push_back({vertices[size_t(t[0])], vertices[size_t(t[1])], vertices[size_t(t[2])]});
    return out;
  }
};

// The mesh without vertices no triangle uses, the others renumbered in order.
TriMesh without_loose_vertices(const TriMesh& mesh);

}  // namespace c3d

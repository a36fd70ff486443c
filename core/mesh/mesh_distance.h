#pragma once
// Each point's distance to the nearest triangle of a mesh (CGAL's AABB tree):
// the ladder's cloud-to-mesh deviation, on the CPU and the same on every
// machine, as the store's figures must be.
#include <vector>

#include "core/mesh/tri_mesh.h"

namespace c3d {

std::vector<double> distances_to_mesh(const std::vector<Vec3>& points, const TriMesh& mesh);

}  // namespace c3d

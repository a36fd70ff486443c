#pragma once
// The lighter levels of the mesh ladder: a dense mesh simplified to a face
// budget by edge collapse (CGAL, Garland-Heckbert quadrics), and the closed
// hull of level 1 (CGAL's alpha wrap). CGAL's second translation unit here.
#include <cstddef>
#include <vector>

#include "core/mesh/tri_mesh.h"

namespace c3d {

// Edge collapse with Garland and Heckbert's plane quadrics until at most
// `faces` faces remain (CGAL 5.5 stops on an edge count: 1.5 edges a face
// is a closed mesh's ratio, so the result lands at or under the budget).
// Edges on the mesh's open border, and those `keep` marks (vertex pairs, in
// either order), are not collapsed and their vertices stay where they are.
TriMesh simplified(const TriMesh& mesh, size_t faces, const std::vector<std::array<int, 2>>& keep = {});

// A closed, 2-manifold wrap of the points (CGAL alpha_wrap_3), alpha first
// set so that triangles alpha across would cover the points' bounding box
// with `max_faces`, grown by half again while the wrap has more; the offset
// is a thirtieth of alpha, the points thinned to one per alpha/3 cube.
TriMesh wrapped(const std::vector<Vec3>& points, size_t max_faces);

}  // namespace c3d

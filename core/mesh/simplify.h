#pragma once
// The lighter levels of the mesh ladder: a dense mesh simplified to a face
// budget by edge collapse (CGAL, Lindstrom-Turk: Garland-Heckbert's plane
// quadrics tore the hips off CGAL's building.ply at level 2), and the closed
// hull of level 1 (CGAL's alpha wrap). CGAL's second translation unit here.
#include <cstddef>
#include <vector>

#include "core/mesh/tri_mesh.h"

namespace c3d {

// Edge collapse (CGAL's Lindstrom-Turk cost and placement) until at most
// `faces` faces remain (CGAL 5.5 stops on an edge count: 1.5 edges a face
// is a closed mesh's ratio, so the result lands at or under the budget).
// Two stages (seed 002): edges on the mesh's open border, and those `keep`
// marks (vertex pairs, in either order), are first not collapsed and their
// vertices stay; if that leaves more faces than the budget, the marked ones
// collapse too. The open border always stays: a level with much border may
// end above its budget (its face count says so).
// Holes whose border is at most `small_hole` long (m) are filled first: gaps
// in the sampling, whose borders would otherwise all be kept.
// No collapse puts a vertex farther than `reach` (m) from the mesh it
// started from, or turns a face over.
TriMesh simplified(const TriMesh& mesh, size_t faces, double small_hole, double reach,
                   const std::vector<std::array<int, 2>>& keep = {});

// A closed, 2-manifold wrap of the points (CGAL alpha_wrap_3), alpha first
// set so that triangles alpha across would cover the points' bounding box
// with `max_faces`, grown by half again while the wrap has more; the offset
// is a thirtieth of alpha, the points thinned to one per alpha/3 cube.
struct Wrap {
  TriMesh mesh;
  double alpha = 0, offset = 0;  // m: what it cannot enter, how far outside the points it lies
};
Wrap wrapped(const std::vector<Vec3>& points, size_t max_faces);

}  // namespace c3d

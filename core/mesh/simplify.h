#pragma once
// The lighter levels of the mesh ladder: a dense mesh simplified to a face
// budget by edge collapse (CGAL, Lindstrom-Turk: Garland-Heckbert's plane
// quadrics tore the hips off CGAL's building.ply at level 2) within the
// mesh's regions first (seed 002), and the closed
// hull of level 1 (CGAL's alpha wrap). CGAL's second translation unit here.
#include <cstddef>
#include <string>
#include <vector>

#include "core/mesh/regions.h"
#include "core/mesh/tri_mesh.h"

namespace c3d {

// How a dense level is made lighter: the two-stage boundary-aware collapse
// of seed 002 (the ladder's), and the three it is compared with
// (docs/meshes.md): plain edge collapse by Lindstrom and Turk's cost (CGAL's
// default), by Garland and Heckbert's plane quadrics, and vertex clustering
// (Open3D) at the cell size that meets the budget.
enum class Simplifier { BoundaryAware, LindstromTurk, GarlandHeckbert, VertexClustering };
const char* simplifier_name(Simplifier s);
Simplifier simplifier_named(const std::string& name);  // throws std::invalid_argument naming the choices

// Stage one's retention by region kind, as weights on one share found so
// that the regions' targets fill the face budget: a plane is told by its
// border and needs few faces inside it; a curved surface needs its inner
// vertices. Detail is kept like a plane: on a scanned mesh most of it is
// noise, and weighted 8 it spent the budget there (docs/meshes.md).
struct RegionRetention {
  double planar = 1, curved = 4, detail = 1;
};

struct Simplified {
  TriMesh mesh;
  std::vector<int> face_region;  // per face: the region of `regions` it lies in (-1: none)
};

// The mesh with at most `faces` faces (CGAL 5.5 stops edge collapse on an
// edge count: 1.5 edges a face is a closed mesh's ratio, so the result lands
// at or under the budget). BoundaryAware, in two stages (seed 002): first
// each region of `regions` collapses only inside itself, down to its own
// retention, its borders with other regions kept; then, if more faces than
// the budget are left, the borders and the open border give up vertices along
// themselves, each region's corners and a planar region's extremes kept: a
// level of many small regions may end above its budget (its face count says
// so). The other methods keep the mesh's open border (collapsing it freely
// pulled a box's walls up from their bottom edge by a metre), and so may end
// above it too.
// Holes whose border is at most `small_hole` long (m) are filled first: gaps
// in the sampling, whose borders would otherwise all be kept.
// No collapse puts a vertex farther than `reach` (m) from the mesh it
// started from, or turns a face over.
Simplified simplified(const TriMesh& mesh, size_t faces, double small_hole, double reach,
                      const MeshRegions& regions, Simplifier how = Simplifier::BoundaryAware,
                      const RegionRetention& retention = {});

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

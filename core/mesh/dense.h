#pragma once
// Level 4 of the mesh ladder: a dense surface through a building's points
// (seeds 002 and 003). Parameters come from the points' spacing
// (spacing.h). CGAL (normals, advancing front) and Open3D (the others) do
// the meshing, each in one translation unit: their headers compile slowly.
#include <string>
#include <vector>

#include "core/mesh/spacing.h"
#include "core/mesh/tri_mesh.h"

namespace c3d {

enum class DenseMethod {
  BallPivoting,    // Open3D, multi-scale: interpolates the points, gaps stay open (seed 002's choice)
  AdvancingFront,  // CGAL: interpolating as well, its triangles no longer than the pivot's ball
  Poisson,         // Open3D's screened Poisson, trimmed where it strays from the points
  AlphaShape,      // Open3D: the points' alpha shape (seed 003); none for exactly flat points
};
const char* dense_method_name(DenseMethod m);
// "pivot", "front", "poisson" or "alpha"; throws std::invalid_argument otherwise.
DenseMethod dense_method_named(const std::string& name);

// Unit normals by PCA over each point's k nearest, oriented along a minimum
// spanning tree from the highest point, whose normal points up: outward on
// a building's roofs and walls.
std::vector<Vec3> oriented_normals(const std::vector<Vec3>& points, int k = 12);

struct DenseResult {
  TriMesh mesh;
  size_t trimmed = 0;  // faces dropped as farther than two spacings from every point
};

// Each method's parameters come from the spacing (open3d_mesh.h). Advancing
// front: no triangle edge longer than the largest pivoting ball's diameter,
// so gaps stay holes. Every method: faces with a corner or centre farther
// than two mean spacings from every point are dropped (the seeds'
// out-of-bounds faces; for the interpolating methods, triangles across a gap).
DenseResult dense_mesh(const std::vector<Vec3>& points, const PointSpacing& spacing, DenseMethod method);

}  // namespace c3d

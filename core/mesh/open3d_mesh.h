#pragma once
// Dense meshes by Open3D (core/mesh/open3d_mesh.cpp): ball pivoting and
// screened Poisson, their parameters from the points' spacing (seed 003).
#include <vector>

#include "core/mesh/spacing.h"
#include "core/mesh/tri_mesh.h"

namespace c3d {

// Poisson's octree depth is bounded: below 5 a building is a blob; above 12
// a cell is under a thousandth of its extent, finer than any scan here.
constexpr int kMinPoissonDepth = 5, kMaxPoissonDepth = 12;

// Ball radii of the multi-scale pivot, smallest first: seed 003's table 2
// (mean and largest nearest-neighbour distance, and 3 x the mean), the
// largest taken as the 95th percentile so one stray point does not set it.
std::vector<double> pivoting_radii(const PointSpacing& s);
// The octree depth whose cells are the mean spacing across the points'
// bounding cube (1.1 times their extent, as Open3D takes it).
int poisson_depth(const std::vector<Vec3>& points, const PointSpacing& s);

// Ball pivoting through the points (their oriented normals given): it
// interpolates the points and leaves gaps open.
TriMesh ball_pivoting(const std::vector<Vec3>& points, const std::vector<Vec3>& normals, const PointSpacing& s);
// Screened Poisson (Kazhdan and Hoppe 2013) at poisson_depth; one thread,
// so the same points give the same mesh. Closed: the caller trims it.
TriMesh screened_poisson(const std::vector<Vec3>& points, const std::vector<Vec3>& normals, const PointSpacing& s);

// The alpha shape of the points (Edelsbrunner and Muecke) at alpha = their
// largest nearest-neighbour distance, seed 003's finest level (table 1), the
// 95th percentile as above.
TriMesh alpha_shape(const std::vector<Vec3>& points, const PointSpacing& s);

// Open3D's vertex clustering of a mesh: one vertex per cube of side `cell`
// (m), at the mean of the vertices in it; faces that fall to a line or a
// point dropped.
TriMesh vertex_clustering(const TriMesh& mesh, double cell);

}  // namespace c3d

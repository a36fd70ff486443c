#pragma once
// How well a mesh level follows its building's points (seed 003's
// cloud-to-mesh deviation, seed 002's faces and extents): per level, for
// summary.json, the store and the report.
#include <cstddef>
#include <vector>

#include "core/mesh/spacing.h"
#include "core/mesh/tri_mesh.h"

namespace c3d {

struct MeshMetrics {
  size_t faces = 0, vertices = 0;
  // Cloud to mesh: each point's distance to the nearest triangle (m), by the
  // evaluation's FaceIndex (core/evaluate).
  double mean = 0, std = 0, p95 = 0, max = 0;
  double mesh_to_cloud = 0;  // one-sided Hausdorff: the farthest vertex or face centre from any point (m)
  double far_share = 0;      // points farther than two mean spacings from the mesh: its holes
  bool closed = false;       // every edge has exactly two faces
  bool manifold = false;     // no edge has more than two faces
  double volume = 0;         // m3, enclosed by a closed mesh (0 when open)
};

// The area of the faces that look up: their normal's z at least
// `min_normal_z` (0.5: roofs sloping less than 60°; walls look sideways, a
// floor down). On a closed hull of a building, its roof area.
double upward_area(const TriMesh& mesh, double min_normal_z = 0.5);

// Each point's distance to the mesh's nearest triangle (m), by the
// evaluation's FaceIndex; infinite where every triangle is degenerate.
std::vector<double> distances_to(const TriMesh& mesh, const std::vector<Vec3>& points);

// Mean, standard deviation, 95th percentile and largest of distances (all 0
// when there are none).
struct Spread {
  double mean = 0, std = 0, p95 = 0, max = 0;
};
Spread spread_of(std::vector<double> d);

MeshMetrics measure_mesh(const TriMesh& mesh, const std::vector<Vec3>& points, const PointSpacing& spacing);

}  // namespace c3d

#pragma once
// The optimizer on by default for curved buildings (seed 000, issue 48): the
// dense mesh of a building's points, snapped onto the surfaces of its exact
// shape, and what that did to it (MeshRefinement, core/types.h).
#include <vector>

#include "core/optimizer/optimizer.h"
#include "core/types.h"

namespace c3d {

struct RefinedMesh {
  TriMesh mesh;  // local coordinates
  MeshRefinement effect;
};

// `points`: the parcel's points; those within kNearModelM of the building's
// model are meshed (greedy projection, its radius from `spacing`). None
// (effect.triangles 0) without an exact shape or a mesh of the points.
RefinedMesh refine_curved(const Building& b, const std::vector<Vec3>& points, double spacing,
                          ComputeDevice device);

}  // namespace c3d

#pragma once
// Midpoint subdivision, shared by the optimizer's planar and curved halves
// (seed 000's surface junction optimization).
#include <vector>

#include "core/optimizer/optimizer.h"

namespace c3d {

// Splits each marked triangle into four at its edge midpoints (new vertices
// appended, at the midpoints); a neighbour sharing a split edge is split too
// (into 2 or 3), so the mesh stays conforming. `labels` (one per triangle)
// pass to the pieces. Returns how many triangles were marked.
int subdivide_marked(TriMesh& mesh, std::vector<int>& labels, const std::vector<char>& marked);

}  // namespace c3d

#pragma once
// Small raster helpers of the LoD 1.3 layering: cells of an nx x ny grid,
// numbered row by row.
#include <vector>

#include "core/types.h"

namespace c3d::lod13 {

// The up to eight cells around cell i.
std::vector<int> neighbours8(int nx, int ny, int i);

// The 4-connected patches of `cells` (diagonal contact joins nothing: two
// patches touching at a corner would pinch the shell there).
std::vector<std::vector<int>> connected_patches(int nx, int ny, const std::vector<int>& cells);

}  // namespace c3d::lod13

#pragma once
// Merging the coplanar components of one roof (over-segmentation from noise).
#include <vector>

#include "core/reconstruct/segment/segmentation.h"

namespace c3d {

// Repeatedly merges the first pair (i < j, in index order) whose planes are
// within 6 degrees and each within `tol` of the other's centroid: j's points
// join i, i is refitted (fit_plane_robust), j is erased. A pair neither of
// whose fits changed since it was last tested is not tested again, so the
// work grows with the pairs and the merges, not with their product.
void merge_coplanar(const std::vector<Vec3>& pts, std::vector<RoofComponent>& comps, double tol);

}  // namespace c3d

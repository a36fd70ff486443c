#pragma once
// A curved primitive refitted to its points by least squares on their
// distances to its surface (Levenberg-Marquardt from RANSAC's estimate).
#include <vector>

#include "core/primitives/primitives.h"

namespace c3d {

// The same kind of surface, its parameters moved to the least sum of squared
// distances of `points`; a plane is refitted by PCA. Inliers are not touched.
Primitive refit(const Primitive& start, const std::vector<Vec3>& points);

}  // namespace c3d

#pragma once
// A curved primitive refitted to its points by least squares on their
// distances to its surface (Levenberg-Marquardt from RANSAC's estimate).
#include <utility>
#include <vector>

#include "core/primitives/primitives.h"

namespace c3d {

// The same kind of surface, its parameters moved to the least sum of squared
// distances of `points`; a plane is refitted by PCA. Inliers are not touched.
Primitive refit(const Primitive& start, const std::vector<Vec3>& points);

// The fitted surface moved by one standard error each way along each
// principal direction of its parameters' covariance (s^2 (J'J)^-1 at the
// fit, s^2 the residual variance): an area's changes over these pairs, in
// quadrature, are its sigma from the fit. None for a plane.
std::vector<std::pair<Primitive, Primitive>> fit_variations(const Primitive& fitted, const std::vector<Vec3>& points);

}  // namespace c3d

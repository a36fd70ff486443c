#pragma once
// The surfaces of a curved building's exact shape (ExactShape, core/types.h)
// as the optimizer snaps onto them: each profile step turned about its axis
// or swept along its path, bounded where the step ends.
#include <vector>

#include "core/optimizer/optimizer.h"
#include "core/types.h"

namespace c3d {

// Turned: a line is a cylinder, a cone or a horizontal plane, an arc centred
// on the axis a sphere, a spline a band of cones along its points (arcs off
// the axis, tori, are left out). Swept: a line is a plane, an arc a
// cylinder along the path; both end caps are planes, but a hall's under a
// free-form roof, whose roof is its B-spline height field. Local coordinates.
std::vector<CurvedPrimitive> exact_surfaces(const ExactShape& shape);

}  // namespace c3d

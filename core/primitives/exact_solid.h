#pragma once
// A curved building's exact shape (ExactShape, core/types.h) as an
// OpenCASCADE solid: cylinders, spheres, cones and B-spline surfaces of
// revolution where its faces have chords. STEP writes it.
#include <TopoDS_Shape.hxx>

#include <string>

#include "core/types.h"

namespace c3d {

// Its parts turned or swept and fused into one solid; std::runtime_error
// saying why when they do not make one.
TopoDS_Shape exact_solid(const ExactShape& shape);

}  // namespace c3d

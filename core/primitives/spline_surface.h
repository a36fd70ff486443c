#pragma once
// A free-form roof's surface (SplineSurface, core/types.h) as OpenCASCADE
// holds it, and back.
#include <Geom_BSplineSurface.hxx>

#include "core/types.h"

namespace c3d {

// OpenCASCADE's surface of s (distinct knots with their multiplicities).
Handle(Geom_BSplineSurface) occ_surface(const SplineSurface& s);
// The plain data of a non-rational surface.
SplineSurface plain_surface(const Geom_BSplineSurface& s);

}  // namespace c3d

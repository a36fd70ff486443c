#pragma once
// Conversions between the plain polygon types and GEOS (C++ API), shared by the
// reconstruction's polygon operations and the cadastre module. Kept out of
// widely included headers: GEOS headers are heavy.
#include <geos/geom/Geometry.h>
#include <geos/geom/GeometryFactory.h>

#include <memory>

#include "core/types.h"

namespace c3d {

// A GEOS (Multi)Polygon; rings are closed here. Throws geos exceptions on
// rings with fewer than 3 vertices.
std::unique_ptr<geos::geom::Geometry> to_geos(const MultiPolygon2& shape,
                                              const geos::geom::GeometryFactory& factory);
// Polygonal parts of any GEOS geometry (collections included), outer rings CCW,
// holes CW, closing vertex dropped.
MultiPolygon2 from_geos(const geos::geom::Geometry& g);

}  // namespace c3d

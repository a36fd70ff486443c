// Faces to indexed triangles for the writers: the constrained Delaunay
// triangulation lives in core (core/solid_check), shared with the solid check.
#include "core/check/solid_check.h"
#include "ifc_citygml/detail.h"

namespace c3d::exp {

Triangles triangulate(const Face& face) {
  IndexedTriangles t = triangulate_indexed(face);
  return Triangles{std::move(t.points), std::move(t.tris)};
}

}  // namespace c3d::exp

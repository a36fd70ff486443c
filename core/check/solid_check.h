#pragma once
// Validity of a building shell (the closed solid of walls, ground and roof) and
// the face triangulation every consumer of planar faces shares. CGAL stays in
// solid_check.cpp: this header is cheap to include.
#include <string>
#include <array>
#include <vector>

#include "core/types.h"

namespace c3d {

struct Triangle {
  Vec3 a, b, c;  // counter-clockwise seen from the side the face normal points to
};

// Triangulates a planar face with holes (CGAL constrained Delaunay in the face
// plane). Triangles keep the orientation of the outer ring and use the face's own
// 3D vertices; a self-intersecting ring still triangulates (crossings become
// vertices lifted onto the plane). Fewer than 3 distinct vertices: empty.
std::vector<Triangle> triangulate(const Face& face);
// The same triangulation as shared vertices + index triples (ring vertices first,
// then any vertex created where rings cross), for writers of indexed meshes.
struct IndexedTriangles {
  std::vector<Vec3> points;
  std::vector<std::array<int, 3>> tris;
};
IndexedTriangles triangulate_indexed(const Face& face);
std::vector<Triangle> triangulate(const std::vector<Face>& faces);
// Whether two triangles of the face's triangulation lean more than tol_deg
// apart (val3dity's 204 compares each with the first it draws; any pair is
// the same test whatever the order). Every triangle counts, however thin:
// the envelope leaves none thin enough to tilt (slivers.h).
bool tilted_triangle(const Face& face, double tol_deg);

struct SolidProblem {
  std::string code;     // see check_solid
  std::string message;  // names the faces involved
  bool warning = false; // reported, but the solid is still valid
};

struct SolidCheck {
  bool ok = false;
  std::vector<SolidProblem> problems;
  double volume = 0;  // CGAL PMP volume of the triangulated shell (0 when not closed)
  double area = 0;    // total triangulated area
  // "ok", or the codes and messages of the errors (not warnings), one line.
  std::string summary() const;
  bool has(const std::string& code) const;
};

// Checks a shell of planar faces, outward oriented. Vertices within 1e-6 m are
// merged and a vertex lying on another face's edge splits it (T-junctions are
// legal in a B-rep). Problem codes:
//   empty, degenerate_face (< 3 distinct vertices), zero_area_face,
//   duplicate_vertex (warning: consecutive repeated vertex), non_planar (a vertex
//   farther than planarity_tol from the face plane), not_closed (boundary edges),
//   non_manifold (edge of > 2 faces or pinched vertex), inconsistent_orientation
//   (neighbouring faces disagree: a flipped face), inward_orientation (the whole
//   shell is inside out), self_intersection, non_positive_volume.
SolidCheck check_solid(const std::vector<Face>& shell, double planarity_tol = 0.01);

}  // namespace c3d

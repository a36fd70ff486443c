// Which element each solid face lies on, and what of each element face the
// solid leaves out: the face minus the solid's faces on it, computed by GEOS in
// the face's own plane. The solid's roof is the element roofs clipped inside the
// walls, so for a roof this is its overhang; an outer ceiling or a hanging roof
// stays whole.
#include "ifc_citygml/surfaces.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <set>

#include "core/geometry/geometry.h"
#include "core/geometry/polygon_ops.h"
#include "ifc_citygml/detail.h"

namespace c3d::exp {
namespace {

constexpr double kCoplanarCos = 0.999;   // normals within 2.6 degrees: one plane (as solid_face_type)
constexpr double kCoplanarDist = 0.01;   // m off the plane: one plane (as solid_face_type)
constexpr double kMinOverlap = 1e-6;     // m2 a solid face must share with an element face to lie on it
constexpr double kMinPiece = 1e-4;       // m2: smaller leftovers are overlay noise of the weld
constexpr double kMinWidth = 0.002;      // m: thinner leftovers are the weld's mm offsets, no surface
constexpr double kSameVertex = 1e-6;     // m in the plane: a result vertex is an input vertex

// Orthonormal frame of a face's plane: (u, v) counter-clockwise seen from outside.
struct PlaneFrame {
  Vec3 o, u, v, n;
  explicit PlaneFrame(const Face& f) : n(unit_normal(f)) {
    o = Vec3::Zero();
    for (const auto& p : f.ring) o += p;
    o /= double(f.ring.size());
    const Vec3 a = std::abs(n.z()) < 0.9 ? Vec3::UnitZ() : Vec3::UnitX();
    u = a.cross(n).normalized();
    v = n.cross(u);
  }
  Vec2 to2(const Vec3& p) const { return {(p - o).dot(u), (p - o).dot(v)}; }
  Vec3 to3(const Vec2& q) const { return o + q.x() * u + q.y() * v; }
};

Ring2 project(const PlaneFrame& fr, const Ring3& r, bool ccw) {
  Ring2 out;
  for (const auto& p : r) out.push_back(fr.to2(p));
  if ((signed_area(out) > 0) != ccw) std::reverse(out.begin(), out.end());
  return out;
}

Polygon2 project(const PlaneFrame& fr, const Face& f) {
  Polygon2 p{project(fr, f.ring, true), {}};
  for (const auto& h : f.holes) p.holes.push_back(project(fr, h, false));
  return p;
}

bool coplanar(const Face& f, const Face& g) {
  const Vec3 ng = unit_normal(g);
  if (unit_normal(f).dot(ng) < kCoplanarCos) return false;
  for (const auto& p : f.ring)
    if (std::abs((p - g.ring.front()).dot(ng)) > kCoplanarDist) return false;
  return true;
}

// The element a solid face lies on: the one whose face it repeats (`m`),
// else the coplanar element face it overlaps most (a roof clipped inside
// the walls).
int owner(const Building& b, const Face& f, const std::array<int, 2>& m) {
  if (m[0] >= 0) return m[0];
  int best = -1;
  double most = kMinOverlap;
  for (size_t e = 0; e < b.elements.size(); ++e)
    for (const auto& g : b.elements[e].faces) {
      if (!coplanar(f, g)) continue;
      const PlaneFrame fr(g);
      const double shared = area(poly::intersect({project(fr, g)}, {project(fr, f)}));
      if (shared > most) most = shared, best = int(e);
    }
  return best;
}

Ring3 lift(const PlaneFrame& fr, const Ring2& r, const std::vector<Vec3>& known) {
  Ring3 out;
  for (const auto& q : r) {
    Vec3 p = fr.to3(q);
    for (const auto& k : known)
      if ((fr.to2(k) - q).norm() < kSameVertex) { p = k; break; }
    out.push_back(p);
  }
  return out;
}

bool thin(const Polygon2& p) {
  double perimeter = 0;
  auto add = [&](const Ring2& r) {
    for (size_t i = 0; i < r.size(); ++i) perimeter += (r[(i + 1) % r.size()] - r[i]).norm();
  };
  add(p.outer);
  for (const auto& h : p.holes) add(h);
  const double a = area(p);
  return a < kMinPiece || 2 * a / perimeter < kMinWidth;
}

// What of element face g the solid's faces `covering` (on g's plane) leave out.
std::vector<Face> left_out(const Face& g, const std::vector<const Face*>& covering) {
  if (covering.empty()) return {g};
  const PlaneFrame fr(g);
  std::vector<Vec3> known = g.ring;
  for (const auto& h : g.holes) known.insert(known.end(), h.begin(), h.end());
  std::vector<MultiPolygon2> cover;
  for (const Face* f : covering) {
    cover.push_back({project(fr, *f)});
    for (const auto& p : f->ring) known.push_back(p);
  }
  std::vector<Face> out;
  for (const auto& piece : poly::subtract({project(fr, g)}, poly::unite_all(cover))) {
    if (thin(piece)) continue;
    Face f;
    f.ring = lift(fr, piece.outer, known);
    for (const auto& h : piece.holes) f.holes.push_back(lift(fr, h, known));
    out.push_back(std::move(f));
  }
  return out;
}

// The element face each solid face repeats ({-1, -1}: none). A curved
// roof's thousands of triangles are copied into the solid as they are:
// found by their exact vertices first, the 1 mm search only for the rest.
std::vector<std::array<int, 2>> repeated_faces(const Building& b) {
  std::map<std::vector<double>, std::array<int, 2>> exact;
  auto key = [](const Face& f) {
    std::vector<double> k;
    for (const Vec3& q : f.ring) k.insert(k.end(), {q.x(), q.y(), q.z()});
    k.push_back(double(f.holes.size()));
    return k;
  };
  for (size_t e = 0; e < b.elements.size(); ++e)
    for (size_t k = 0; k < b.elements[e].faces.size(); ++k)
      exact.emplace(key(b.elements[e].faces[k]), std::array<int, 2>{int(e), int(k)});
  std::vector<std::array<int, 2>> out;
  for (const Face& f : b.solid) {
    const auto it = exact.find(key(f));
    out.push_back(it != exact.end() ? it->second : matching_element_face(b, f));
  }
  return out;
}

}  // namespace

BuildingSurfaces building_surfaces(const Building& b) {
  BuildingSurfaces s;
  const std::vector<std::array<int, 2>> match = repeated_faces(b);
  std::set<std::array<int, 2>> in_solid(match.begin(), match.end());
  for (size_t j = 0; j < b.solid.size(); ++j) {
    const int e = owner(b, b.solid[j], match[j]);
    const ElementType t = e >= 0 ? b.elements[e].type : solid_face_type(b, b.solid[j]);
    s.solid.push_back({b.solid[j], t, e, int(j)});
  }
  for (size_t e = 0; e < b.elements.size(); ++e)
    for (size_t k = 0; k < b.elements[e].faces.size(); ++k) {
      if (in_solid.count({int(e), int(k)})) continue;  // the solid holds this very face
      const Face& g = b.elements[e].faces[k];
      std::vector<const Face*> covering;
      for (const auto& p : s.solid)
        if (p.element == int(e) && coplanar(p.face, g)) covering.push_back(&p.face);
      for (auto& f : left_out(g, covering)) s.outside.push_back({std::move(f), b.elements[e].type, int(e), -1});
    }
  return s;
}

}  // namespace c3d::exp

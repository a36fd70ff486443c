#include "core/mesh/simplify.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/Constrained_placement.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/Count_stop_predicate.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/LindstromTurk_placement.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/Bounded_normal_change_filter.h>
#include <CGAL/Surface_mesh_simplification/edge_collapse.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/repair_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/border.h>
#include <CGAL/Polygon_mesh_processing/triangulate_hole.h>
#include <CGAL/alpha_wrap_3.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <set>

namespace c3d {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Mesh = CGAL::Surface_mesh<Point>;
namespace SMS = CGAL::Surface_mesh_simplification;
namespace PMP = CGAL::Polygon_mesh_processing;
using Triangle = Kernel::Triangle_3;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, CGAL::AABB_triangle_primitive<Kernel, std::vector<Triangle>::const_iterator>>>;

// The mesh in CGAL's form, made a 2-manifold first: an alpha shape's or a
// pivot's triangles may share an edge three times, or touch at a vertex
// only; the polygon soup repair splits such vertices and orients the faces.
Mesh to_surface_mesh(const TriMesh& t) {
  std::vector<Point> points;
  points.reserve(t.vertices.size());
  for (const Vec3& p : t.vertices) points.emplace_back(p.x(), p.y(), p.z());
  std::vector<std::vector<std::size_t>> faces;
  faces.reserve(t.triangles.size());
  for (const auto& f : t.triangles) faces.push_back({std::size_t(f[0]), std::size_t(f[1]), std::size_t(f[2])});
  PMP::repair_polygon_soup(points, faces);
  PMP::orient_polygon_soup(points, faces);
  Mesh m;
  PMP::polygon_soup_to_polygon_mesh(points, faces, m);
  return m;
}

TriMesh from_surface_mesh(Mesh& m) {
  m.collect_garbage();
  TriMesh out;
  for (auto v : m.vertices()) {
    const Point& p = m.point(v);
    out.vertices.emplace_back(p.x(), p.y(), p.z());
  }
  for (auto f : m.faces()) {
    std::array<int, 3> t{};
    int k = 0;
    for (auto v : CGAL::vertices_around_face(m.halfedge(f), m))
      if (k < 3) t[size_t(k++)] = int(v.idx());
    if (k == 3) out.triangles.push_back(t);
  }
  return out;
}

// A collapse whose new vertex lands farther than `reach` from the mesh it
// started from is refused: on a torn pivot mesh an ill-conditioned
// placement flung a vertex 135 m off a 50 m building, on a box's corner 3 m
// above its roof. (CGAL's filters pass an optional placement on; an empty
// one refuses the collapse.)
struct NearTheStart {
  const Tree* start = nullptr;
  double reach = 0;
  template <typename Profile>
  boost::optional<typename Profile::Point> operator()(const Profile&,
                                                      boost::optional<typename Profile::Point> placed) const {
    if (!placed || !start) return placed;
    const Point p = *placed;
    if (start->squared_distance(p) > reach * reach) return boost::none;
    return placed;
  }
};
using SafeFilter = SMS::Bounded_normal_change_filter<NearTheStart>;

// Holes whose border is at most `perimeter` long are sampling gaps, not
// openings: each is triangulated (CGAL), so its border is no edge to keep.
void fill_small_holes(Mesh& m, double perimeter) {
  std::vector<Mesh::Halfedge_index> borders;
  PMP::extract_boundary_cycles(m, std::back_inserter(borders));
  for (Mesh::Halfedge_index h : borders) {
    double length = 0;
    for (auto e : CGAL::halfedges_around_face(h, m))
      length += std::sqrt(CGAL::squared_distance(m.point(m.source(e)), m.point(m.target(e))));
    if (length <= perimeter) PMP::triangulate_hole(m, h, CGAL::Emptyset_iterator());
  }
}

// Edge collapse by Lindstrom and Turk's cost and placement until at most `faces`
// faces remain; edges `fixed` says are not collapsed and their vertices stay.
// No collapse turns a face's normal over (CGAL's bounded normal change) or
// puts its vertex far from the mesh it started from (NearTheStart).
template <typename Fixed>
void collapse(Mesh& m, size_t faces, const SafeFilter& filter, Fixed fixed) {
  auto constrained = m.add_property_map<Mesh::Edge_index, bool>("e:constrained", false).first;
  for (auto e : m.edges()) constrained[e] = fixed(e);
  const SMS::Constrained_placement<SMS::LindstromTurk_placement<Mesh>, decltype(constrained)> placement(constrained);
  const SMS::Count_stop_predicate<Mesh> stop(faces * 3 / 2);
  SMS::edge_collapse(m, stop,
                     CGAL::parameters::get_placement(placement)
                         .edge_is_constrained_map(constrained)
                         .filter(filter));
  m.remove_property_map(constrained);
  m.collect_garbage();
}

// One point per cube of side `cell` (the first met): a wrap of alpha many
// times the cell needs no more, and costs with the points it gets.
std::vector<Point> thinned(const std::vector<Vec3>& points, double cell) {
  std::set<std::array<long, 3>> seen;
  std::vector<Point> out;
  for (const Vec3& p : points) {
    const std::array<long, 3> key = {long(std::floor(p.x() / cell)), long(std::floor(p.y() / cell)),
                                     long(std::floor(p.z() / cell))};
    if (seen.insert(key).second) out.emplace_back(p.x(), p.y(), p.z());
  }
  return out;
}

}  // namespace

TriMesh simplified(const TriMesh& mesh, size_t faces, double small_hole, double reach,
                   const std::vector<std::array<int, 2>>& keep) {
  if (mesh.triangles.size() <= faces) return without_loose_vertices(mesh);
  // Marked edges by their ends' places: the soup repair renumbers vertices.
  using Place = std::array<double, 3>;
  const auto place = [](const auto& p) { return Place{p[0], p[1], p[2]}; };
  std::set<std::pair<Place, Place>> marked;
  for (const auto& e : keep) {
    const Place a = place(mesh.vertices[size_t(e[0])]), b = place(mesh.vertices[size_t(e[1])]);
    marked.insert({std::min(a, b), std::max(a, b)});
  }
  std::vector<Triangle> start;
  for (const auto& t : mesh.soup())
    start.emplace_back(Point(t[0].x(), t[0].y(), t[0].z()), Point(t[1].x(), t[1].y(), t[1].z()),
                       Point(t[2].x(), t[2].y(), t[2].z()));
  start.erase(std::remove_if(start.begin(), start.end(), [](const Triangle& t) { return t.is_degenerate(); }), start.end());
  Tree tree(start.begin(), start.end());
  tree.accelerate_distance_queries();
  const SafeFilter filter(NearTheStart{&tree, reach});
  Mesh m = to_surface_mesh(mesh);
  fill_small_holes(m, small_hole);
  collapse(m, faces, filter, [&](Mesh::Edge_index e) {
    const Place a = place(m.point(m.vertex(e, 0))), b = place(m.point(m.vertex(e, 1)));
    return m.is_border(e) || marked.count({std::min(a, b), std::max(a, b)}) > 0;
  });
  // Stage two: where the marked edges hold more faces than the budget, they
  // collapse too; the open border stays (collapsing it pulled a box's walls
  // up from their bottom edge by a metre).
  if (!keep.empty() && size_t(m.number_of_faces()) > faces)
    collapse(m, faces, filter, [&](Mesh::Edge_index e) { return m.is_border(e); });
  return without_loose_vertices(from_surface_mesh(m));
}

Wrap wrapped(const std::vector<Vec3>& points, size_t max_faces) {
  Wrap out;
  if (points.size() < 4 || max_faces < 4) return out;
  Vec3 lo = points.front(), hi = points.front();
  for (const Vec3& p : points) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  const Vec3 size = (hi - lo).cwiseMax(Vec3::Constant(1e-3));
  const double box_area = 2 * (size.x() * size.y() + size.x() * size.z() + size.y() * size.z());
  // A wrap's triangles are about alpha across (0.43 alpha^2 each): the
  // first alpha spends the budget on the box's surface; it grows by half
  // again while the wrap is over budget.
  for (double alpha = std::sqrt(box_area / (0.43 * double(max_faces))); ; alpha *= 1.5) {
    Mesh wrap;
    CGAL::alpha_wrap_3(thinned(points, alpha / 3), alpha, alpha / 30, wrap);
    out = {from_surface_mesh(wrap), alpha, alpha / 30};
    if (out.mesh.triangles.size() <= max_faces || alpha > size.norm()) break;
  }
  return out;
}

}  // namespace c3d

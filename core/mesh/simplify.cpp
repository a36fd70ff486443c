#include "core/mesh/simplify.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/Constrained_placement.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/Count_stop_predicate.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/GarlandHeckbert_plane_policies.h>
#include <CGAL/Surface_mesh_simplification/edge_collapse.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/repair_polygon_soup.h>
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

TriMesh simplified(const TriMesh& mesh, size_t faces, const std::vector<std::array<int, 2>>& keep) {
  if (mesh.triangles.size() <= faces) return without_loose_vertices(mesh);
  Mesh m = to_surface_mesh(mesh);
  auto constrained = m.add_property_map<Mesh::Edge_index, bool>("e:constrained", false).first;
  std::set<std::pair<int, int>> marked;
  for (const auto& e : keep) marked.insert({std::min(e[0], e[1]), std::max(e[0], e[1])});
  for (auto e : m.edges()) {
    const int a = int(m.vertex(e, 0).idx()), b = int(m.vertex(e, 1).idx());
    constrained[e] = m.is_border(e) || marked.count({std::min(a, b), std::max(a, b)}) > 0;
  }
  using Policies = SMS::GarlandHeckbert_plane_policies<Mesh, Kernel>;
  Policies gh(m);
  const SMS::Constrained_placement<Policies::Get_placement, decltype(constrained)> placement(constrained,
                                                                                             gh.get_placement());
  const SMS::Count_stop_predicate<Mesh> stop(faces * 3 / 2);
  SMS::edge_collapse(m, stop,
                     CGAL::parameters::get_cost(gh.get_cost()).get_placement(placement).edge_is_constrained_map(constrained));
  return without_loose_vertices(from_surface_mesh(m));
}

TriMesh wrapped(const std::vector<Vec3>& points, size_t max_faces) {
  if (points.size() < 4 || max_faces < 4) return {};
  Vec3 lo = points.front(), hi = points.front();
  for (const Vec3& p : points) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  const Vec3 size = (hi - lo).cwiseMax(Vec3::Constant(1e-3));
  const double box_area = 2 * (size.x() * size.y() + size.x() * size.z() + size.y() * size.z());
  // A wrap's triangles are about alpha across (0.43 alpha^2 each): the
  // first alpha spends the budget on the box's surface; it grows by half
  // again while the wrap is over budget.
  TriMesh out;
  for (double alpha = std::sqrt(box_area / (0.43 * double(max_faces))); ; alpha *= 1.5) {
    Mesh wrap;
    CGAL::alpha_wrap_3(thinned(points, alpha / 3), alpha, alpha / 30, wrap);
    out = from_surface_mesh(wrap);
    if (out.triangles.size() <= max_faces || alpha > size.norm()) break;
  }
  return out;
}

}  // namespace c3d

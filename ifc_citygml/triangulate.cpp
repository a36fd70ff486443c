// Planar face -> triangles with CGAL's constrained Delaunay triangulation in the
// face plane; the "inside" domain is found by nesting depth, so holes and
// non-convex outlines come out right.
#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <list>

#include "core/geometry.h"
#include "ifc_citygml/detail.h"

namespace c3d::exp {
namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
struct FaceInfo {
  int depth = -1;
  bool inside() const { return depth % 2 == 1; }
};
using Vb = CGAL::Triangulation_vertex_base_with_info_2<int, K>;
using Fbi = CGAL::Triangulation_face_base_with_info_2<FaceInfo, K>;
using Fb = CGAL::Constrained_triangulation_face_base_2<K, Fbi>;
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
using Cdt = CGAL::Constrained_Delaunay_triangulation_2<K, Tds, CGAL::Exact_predicates_tag>;

// Flood fill from the infinite face: depth grows by one across each constraint.
void mark_domains(Cdt& cdt) {
  std::list<Cdt::Edge> border;
  auto fill = [&](Cdt::Face_handle start, int depth) {
    std::list<Cdt::Face_handle> queue{start};
    while (!queue.empty()) {
      auto f = queue.front();
      queue.pop_front();
      if (f->info().depth != -1) continue;
      f->info().depth = depth;
      for (int i = 0; i < 3; ++i) {
        auto n = f->neighbor(i);
        if (n->info().depth != -1) continue;
        if (cdt.is_constrained({f, i})) border.push_back({f, i});
        else queue.push_back(n);
      }
    }
  };
  fill(cdt.infinite_face(), 0);
  while (!border.empty()) {
    auto e = border.front();
    border.pop_front();
    auto n = e.first->neighbor(e.second);
    if (n->info().depth == -1) fill(n, e.first->info().depth + 1);
  }
}

}  // namespace

Triangles triangulate(const Face& face) {
  Triangles out;
  if (face.ring.size() < 3) return out;
  const Vec3 n = unit_normal(face);
  const Vec3 o = face.ring.front();
  Vec3 u = (std::abs(n.z()) < 0.9 ? Vec3::UnitZ() : Vec3::UnitX()).cross(n).normalized();
  Vec3 v = n.cross(u);  // (u, v, n) right-handed: 2D CCW == face orientation
  Cdt cdt;
  auto add_ring = [&](const Ring3& ring) {
    std::vector<Cdt::Vertex_handle> vh;
    for (const auto& p : ring) {
      auto h = cdt.insert(K::Point_2((p - o).dot(u), (p - o).dot(v)));
      h->info() = int(out.points.size());
      out.points.push_back(p);
      vh.push_back(h);
    }
    for (size_t i = 0; i < vh.size(); ++i)
      if (vh[i] != vh[(i + 1) % vh.size()]) cdt.insert_constraint(vh[i], vh[(i + 1) % vh.size()]);
  };
  add_ring(face.ring);
  for (const auto& h : face.holes) add_ring(h);
  // Vertices the triangulation created (intersecting constraints) are lifted on the plane.
  for (auto vit = cdt.finite_vertices_begin(); vit != cdt.finite_vertices_end(); ++vit) {
    int i = vit->info();
    bool known = i >= 0 && size_t(i) < out.points.size() &&
                 std::abs((out.points[i] - o).dot(u) - vit->point().x()) < 1e-9 &&
                 std::abs((out.points[i] - o).dot(v) - vit->point().y()) < 1e-9;
    if (!known) {
      vit->info() = int(out.points.size());
      out.points.push_back(o + u * vit->point().x() + v * vit->point().y());
    }
  }
  mark_domains(cdt);
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
    if (!f->info().inside()) continue;
    out.tris.push_back({f->vertex(0)->info(), f->vertex(1)->info(), f->vertex(2)->info()});
  }
  return out;
}

}  // namespace c3d::exp

// A hall under a free-form roof (height_field.h): the roof triangulated in
// plan over the footprint and lifted onto the surface, a wall per footprint
// edge up to it, the ground.
#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>

#include <algorithm>
#include <cmath>
#include <queue>

#include "core/geometry/geometry.h"
#include "core/geometry/polygon_ops.h"
#include "core/primitives/height_field.h"
#include "core/primitives/revolution_faces.h"

namespace c3d {

namespace {

constexpr double kFinestStepM = 0.2;

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Fb = CGAL::Constrained_triangulation_face_base_2<K, CGAL::Triangulation_face_base_with_info_2<int, K>>;
using Tds = CGAL::Triangulation_data_structure_2<CGAL::Triangulation_vertex_base_2<K>, Fb>;
using Cdt = CGAL::Constrained_Delaunay_triangulation_2<K, Tds, CGAL::Exact_predicates_tag>;

// Each face's nesting: 0 outside, 1 in the outer ring, 2 in a hole, ...:
// crossing a constrained edge goes one deeper. By the triangulation's own
// edges, not by testing points against the polygon: the cut points of a
// slanted edge are off its line by rounding, and slivers between them lie
// on either side.
void mark_nesting(Cdt& cdt) {
  for (auto f = cdt.all_faces_begin(); f != cdt.all_faces_end(); ++f) f->info() = -1;
  std::queue<std::pair<Cdt::Face_handle, int>> border;
  border.push({cdt.infinite_face(), 0});
  while (!border.empty()) {
    auto [start, level] = border.front();
    border.pop();
    if (start->info() != -1) continue;
    std::queue<Cdt::Face_handle> same;
    same.push(start);
    start->info() = level;
    while (!same.empty()) {
      const Cdt::Face_handle f = same.front();
      same.pop();
      for (int i = 0; i < 3; ++i) {
        const Cdt::Face_handle n = f->neighbor(i);
        if (n->info() != -1) continue;
        if (cdt.is_constrained({f, i})) {
          border.push({n, level + 1});
        } else {
          n->info() = level;
          same.push(n);
        }
      }
    }
  }
}

// A ring's edges, each cut into pieces no longer than `step`: per edge its
// points from start to end.
std::vector<std::vector<Vec2>> cut_edges(const Ring2& ring, double step) {
  std::vector<std::vector<Vec2>> out;
  for (size_t i = 0; i < ring.size(); ++i) {
    const Vec2 p = ring[i], q = ring[(i + 1) % ring.size()];
    const int n = std::max(1, int(std::ceil((q - p).norm() / step)));
    std::vector<Vec2> pts;
    for (int k = 0; k <= n; ++k) pts.push_back(k == n ? q : p + (q - p) * (double(k) / n));
    out.push_back(std::move(pts));
  }
  return out;
}

double distance_to_rings(const Polygon2& p, const Vec2& q) {
  double best = 1e300;
  auto ring = [&](const Ring2& r) {
    for (size_t i = 0; i < r.size(); ++i) {
      const Vec2 a = r[i], d = r[(i + 1) % r.size()] - a;
      const double t = std::clamp((q - a).dot(d) / std::max(d.squaredNorm(), 1e-18), 0.0, 1.0);
      best = std::min(best, (a + t * d - q).norm());
    }
  };
  ring(p.outer);
  for (const Ring2& h : p.holes) ring(h);
  return best;
}

// The surface over polygon `foot` as triangles, facing up: the footprint's
// edges cut every `step`, a grid of `step` inside, Delaunay between them.
std::vector<Face> roof_triangles(const HeightField& f, const Polygon2& foot, double step) {
  Cdt cdt;
  auto constrain = [&](const Ring2& r) {
    for (const std::vector<Vec2>& edge : cut_edges(r, step))
      for (size_t k = 0; k + 1 < edge.size(); ++k)
        cdt.insert_constraint(K::Point_2(edge[k].x(), edge[k].y()), K::Point_2(edge[k + 1].x(), edge[k + 1].y()));
  };
  constrain(foot.outer);
  for (const Ring2& h : foot.holes) constrain(h);
  Vec2 lo = foot.outer.front(), hi = lo;
  for (const Vec2& q : foot.outer) lo = lo.cwiseMin(q), hi = hi.cwiseMax(q);
  for (double y = lo.y() + step / 2; y < hi.y(); y += step)
    for (double x = lo.x() + step / 2; x < hi.x(); x += step)
      if (in_polygon_plan(foot, {x, y}) && distance_to_rings(foot, {x, y}) > 0.4 * step) cdt.insert(K::Point_2(x, y));
  mark_nesting(cdt);
  std::vector<Face> out;
  for (auto fh = cdt.finite_faces_begin(); fh != cdt.finite_faces_end(); ++fh) {
    if (fh->info() % 2 != 1) continue;
    Ring3 tri;
    for (int k = 0; k < 3; ++k) {
      const K::Point_2& p = fh->vertex(k)->point();
      tri.push_back({p.x(), p.y(), f.z({p.x(), p.y()})});
    }
    out.push_back({std::move(tri), {}});
  }
  return out;
}

// One wall per edge of `ring` from the ground up to the surface, facing
// right of its direction; its top through the points the roof's edge is cut at.
void add_walls(const HeightField& f, const Ring2& ring, double ground_z, double step, Building& b) {
  for (const std::vector<Vec2>& edge : cut_edges(ring, step)) {
    if ((edge.back() - edge.front()).norm() < 1e-6) continue;
    Ring3 wall = {{edge.front().x(), edge.front().y(), ground_z}, {edge.back().x(), edge.back().y(), ground_z}};
    for (auto it = edge.rbegin(); it != edge.rend(); ++it) wall.push_back({it->x(), it->y(), f.z(*it)});
    b.elements.push_back(element_of(ElementType::Wall, {{std::move(wall), {}}}));
  }
}

// The roof's sigma: each footprint edge moved out by its own sigma, on its
// own, adds the surface over that strip (the edge's length lifted by the
// roof's slope along it); the shift all edges share adds the whole rim's.
double roof_sigma(const HeightField& f, const Polygon2& foot, const FreeFormInput& in) {
  std::vector<const Ring2*> rings{&foot.outer};
  for (const Ring2& h : foot.holes) rings.push_back(&h);
  double own = 0, rim = 0;
  size_t k = 0;
  for (const Ring2* ring : rings)
    for (size_t i = 0; i < ring->size(); ++i, ++k) {
      const Vec2 a = (*ring)[i], b = (*ring)[(i + 1) % ring->size()];
      double lifted = 0;
      for (int j = 0; j < 8; ++j) lifted += std::sqrt(1 + f.slope(a + (b - a) * ((j + 0.5) / 8)).squaredNorm()) / 8;
      lifted *= (b - a).norm();
      if (k < in.edge_sigma.size()) own += std::pow(lifted * in.edge_sigma[k], 2);
      rim += lifted;
    }
  return std::hypot(std::sqrt(own), rim * in.common_sigma);
}

// The exact part: the footprint's outer ring swept up past the roof, cut
// off above the surface.
ShapePart hall_under(const Ring2& outer, double ground_z, double top_z, const SplineSurface& roof) {
  ShapePart part = hall_part(outer, ground_z, top_z + 1);
  part.roof = roof;
  return part;
}

}  // namespace

std::optional<Building> free_form_building(const FreeFormInput& in) {
  const Polygon2 foot = oriented(in.footprint);
  if (foot.outer.size() < 3 || area(foot) <= 0 || in.roof.empty()) return std::nullopt;
  const HeightField f(in.roof);
  Vec2 lo = foot.outer.front(), hi = lo;
  for (const Vec2& q : foot.outer) lo = lo.cwiseMin(q), hi = hi.cwiseMax(q);
  // Triangles of legs h leave a surface of curvature k within k h^2 / 4;
  // no finer than kFinestStepM (a roof curving to a 1.6 m radius is
  // already left within 1 cm there).
  const double k = f.max_curvature(lo, hi, 0.25);
  const double step = std::clamp(std::sqrt(4 * in.chord / std::max(k, 1e-9)), kFinestStepM, 2.0);
  Building b;
  std::vector<Face> roof = roof_triangles(f, foot, step);
  double top = -1e300;
  for (const Face& t : roof)
    for (const Vec3& q : t.ring) {
      if (q.z() - in.ground_z < kMinWallM) return std::nullopt;  // the roof must stand on walls all round
      top = std::max(top, q.z());
    }
  if (roof.empty()) return std::nullopt;
  b.elements.push_back(element_of(ElementType::Roof, std::move(roof)));
  add_walls(f, foot.outer, in.ground_z, step, b);
  for (const Ring2& h : foot.holes) add_walls(f, h, in.ground_z, step, b);
  b.elements.push_back(element_of(ElementType::Ground, {face_at(foot, in.ground_z, false)}));
  Element& r = b.elements.front();
  r.sigma_area = roof_sigma(f, foot, in);
  if (foot.holes.empty()) b.exact.parts.push_back(hall_under(foot.outer, in.ground_z, top, in.roof));
  close_curved(b, in.building_id, in.ground_z);
  return b;
}

}  // namespace c3d

// Shell validity with CGAL Polygon_mesh_processing, and face triangulation with
// CGAL's constrained Delaunay triangulation (both heavy headers: kept here only).
#include "core/check/solid_check.h"

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <sstream>
#include <unordered_map>

#include "core/geometry/geometry.h"

namespace c3d {
namespace {

namespace PMP = CGAL::Polygon_mesh_processing;
using K = CGAL::Exact_predicates_inexact_constructions_kernel;

// ---- triangulation -------------------------------------------------------

struct VInfo {
  int id = -1;  // index into the face's 3D vertices; -1: created at a crossing
};
struct FInfo {
  int nesting = -1;  // odd: inside the polygon (between outer ring and holes)
};
using Vb = CGAL::Triangulation_vertex_base_with_info_2<VInfo, K>;
using Fbi = CGAL::Triangulation_face_base_with_info_2<FInfo, K>;
using Fb = CGAL::Constrained_triangulation_face_base_2<K, Fbi>;
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
using Cdt = CGAL::Constrained_Delaunay_triangulation_2<K, Tds, CGAL::Exact_predicates_tag>;

// Flood fill from the infinite face; every constraint crossed adds one nesting level.
void mark_nesting(Cdt& cdt) {
  for (auto f : cdt.all_face_handles()) f->info().nesting = -1;
  std::vector<std::pair<Cdt::Face_handle, int>> seeds{{cdt.infinite_face(), 0}};
  while (!seeds.empty()) {
    auto [start, level] = seeds.back();
    seeds.pop_back();
    if (start->info().nesting != -1) continue;
    std::vector<Cdt::Face_handle> stack{start};
    start->info().nesting = level;
    while (!stack.empty()) {
      auto f = stack.back();
      stack.pop_back();
      for (int i = 0; i < 3; ++i) {
        auto n = f->neighbor(i);
        if (n->info().nesting != -1) continue;
        if (cdt.is_constrained({f, i})) {
          seeds.push_back({n, level + 1});
        } else {
          n->info().nesting = level;
          stack.push_back(n);
        }
      }
    }
    // Breadth by level: finish the shallower levels first.
    std::sort(seeds.begin(), seeds.end(),
              [](const auto& a, const auto& b) { return a.second > b.second; });
  }
}

// Orthonormal in-plane axes (u, v) with u x v = n.
std::pair<Vec3, Vec3> plane_axes(const Vec3& n) {
  Vec3 a = std::abs(n.x()) < 0.6 ? Vec3::UnitX() : Vec3::UnitY();
  Vec3 u = a.cross(n).normalized();
  return {u, n.cross(u)};
}

}  // namespace

IndexedTriangles triangulate_indexed(const Face& face) {
  IndexedTriangles out;
  if (face.ring.size() < 3) return out;
  Vec3 n = newell_normal(face.ring);
  if (n.norm() == 0) return out;
  if (face.ring.size() == 3 && face.holes.empty()) {
    out.points = face.ring;
    out.tris.push_back({0, 1, 2});
    return out;
  }
  n.normalize();
  const auto [u, v] = plane_axes(n);
  const Vec3 o = face.ring.front();

  Cdt cdt;
  auto add_ring = [&](const Ring3& ring) {
    std::vector<Cdt::Vertex_handle> vh;
    for (const auto& p : ring) {
      Vec3 d = p - o;
      auto h = cdt.insert(K::Point_2(d.dot(u), d.dot(v)));
      if (h->info().id < 0) {
        h->info().id = int(out.points.size());
        out.points.push_back(p);
      }
      vh.push_back(h);
    }
    for (size_t i = 0; i < vh.size(); ++i) {
      auto a = vh[i], b = vh[(i + 1) % vh.size()];
      if (a != b) cdt.insert_constraint(a, b);
    }
  };
  add_ring(face.ring);
  for (const auto& h : face.holes) add_ring(h);
  mark_nesting(cdt);
  // Vertices created where constraints cross are lifted onto the face plane.
  for (auto vit = cdt.finite_vertices_begin(); vit != cdt.finite_vertices_end(); ++vit)
    if (vit->info().id < 0) {
      vit->info().id = int(out.points.size());
      out.points.push_back(o + vit->point().x() * u + vit->point().y() * v);
    }
  for (auto f : cdt.finite_face_handles()) {
    if (f->info().nesting % 2 != 1) continue;  // u x v = n: counter-clockwise = the face's side
    out.tris.push_back({f->vertex(0)->info().id, f->vertex(1)->info().id, f->vertex(2)->info().id});
  }
  return out;
}

std::vector<Triangle> triangulate(const Face& face) {
  IndexedTriangles t = triangulate_indexed(face);
  std::vector<Triangle> out;
  out.reserve(t.tris.size());
  for (const auto& tri : t.tris) out.push_back({t.points[tri[0]], t.points[tri[1]], t.points[tri[2]]});
  return out;
}

std::vector<Triangle> triangulate(const std::vector<Face>& faces) {
  std::vector<Triangle> out;
  for (const auto& f : faces) {
    auto t = triangulate(f);
    out.insert(out.end(), t.begin(), t.end());
  }
  return out;
}

// ---- shell check ----------------------------------------------------------

std::string SolidCheck::summary() const {
  std::string s;
  for (const auto& p : problems) {
    if (p.warning) continue;
    if (!s.empty()) s += "; ";
    s += p.code + ": " + p.message;
  }
  return s.empty() ? "ok" : s;
}

bool SolidCheck::has(const std::string& code) const {
  return std::any_of(problems.begin(), problems.end(),
                     [&](const SolidProblem& p) { return p.code == code; });
}

namespace {

constexpr double kMergeTol = 1e-6;

// Collects problems of one kind and reports them once, naming up to 8 faces.
class Problems {
 public:
  void add(const std::string& code, const std::string& what, bool warning = false) {
    auto& e = by_code_[code];
    if (e.count++ < 8) e.items += (e.items.empty() ? "" : ", ") + what;
    e.warning = warning;
    if (std::find(order_.begin(), order_.end(), code) == order_.end()) order_.push_back(code);
  }
  std::vector<SolidProblem> list() const {
    std::vector<SolidProblem> out;
    for (const auto& code : order_) {
      const auto& e = by_code_.at(code);
      std::string msg = e.items + (e.count > 8 ? " and " + std::to_string(e.count - 8) + " more" : "");
      out.push_back({code, msg, e.warning});
    }
    return out;
  }

 private:
  struct Entry {
    int count = 0;
    std::string items;
    bool warning = false;
  };
  std::map<std::string, Entry> by_code_;
  std::vector<std::string> order_;
};

std::string fmt(double v) {
  std::ostringstream s;
  s.precision(3);
  s << v;
  return s.str();
}

// Per-face checks that need no topology.
void check_faces(const std::vector<Face>& shell, double tol, Problems& pr) {
  for (size_t i = 0; i < shell.size(); ++i) {
    const Face& f = shell[i];
    const std::string name = "face " + std::to_string(i);
    std::vector<const Ring3*> rings{&f.ring};
    for (const auto& h : f.holes) rings.push_back(&h);
    for (const Ring3* r : rings) {
      for (size_t k = 0; k < r->size(); ++k) {
        if (((*r)[k] - (*r)[(k + 1) % r->size()]).norm() < kMergeTol) {
          pr.add("duplicate_vertex", name, true);
          break;
        }
      }
    }
    if (f.ring.size() < 3) {
      pr.add("degenerate_face", name);
      continue;
    }
    double a = area(f);
    if (a < 1e-9) {
      pr.add("zero_area_face", name);
      continue;
    }
    Vec3 n = unit_normal(f);
    Vec3 c = Vec3::Zero();
    for (const auto& p : f.ring) c += p;
    c /= double(f.ring.size());
    double worst = 0;
    for (const Ring3* r : rings)
      for (const auto& p : *r) worst = std::max(worst, std::abs((p - c).dot(n)));
    if (worst > tol) pr.add("non_planar", name + " (" + fmt(worst) + " m off its plane)");
  }
}

// Merges vertices within kMergeTol (grid hashing, neighbouring cells searched).
class VertexPool {
 public:
  size_t index(const Vec3& p) {
    const std::array<long long, 3> c = cell(p);
    for (long long dx = -1; dx <= 1; ++dx)
      for (long long dy = -1; dy <= 1; ++dy)
        for (long long dz = -1; dz <= 1; ++dz) {
          auto it = grid_.find(key({c[0] + dx, c[1] + dy, c[2] + dz}));
          if (it == grid_.end()) continue;
          for (size_t i : it->second)
            if ((points[i] - p).norm() <= kMergeTol) return i;
        }
    grid_[key(c)].push_back(points.size());
    points.push_back(p);
    return points.size() - 1;
  }
  std::vector<Vec3> points;

 private:
  static std::array<long long, 3> cell(const Vec3& p) {
    return {(long long)std::floor(p.x() / kMergeTol), (long long)std::floor(p.y() / kMergeTol),
            (long long)std::floor(p.z() / kMergeTol)};
  }
  static std::string key(const std::array<long long, 3>& c) {
    return std::string(reinterpret_cast<const char*>(c.data()), sizeof(c));
  }
  std::unordered_map<std::string, std::vector<size_t>> grid_;
};

// Inserts into every ring the shell vertices lying inside its edges, so that
// faces meeting at a T-junction share the split edge.
std::vector<Face> split_t_junctions(const std::vector<Face>& shell) {
  std::vector<Vec3> verts;
  for (const auto& f : shell) {
    verts.insert(verts.end(), f.ring.begin(), f.ring.end());
    for (const auto& h : f.holes) verts.insert(verts.end(), h.begin(), h.end());
  }
  std::sort(verts.begin(), verts.end(), [](const Vec3& a, const Vec3& b) { return a.x() < b.x(); });
  auto split = [&](const Ring3& ring) {
    Ring3 out;
    for (size_t i = 0; i < ring.size(); ++i) {
      const Vec3 &a = ring[i], &b = ring[(i + 1) % ring.size()];
      out.push_back(a);
      Vec3 d = b - a;
      double len2 = d.squaredNorm();
      if (len2 < kMergeTol * kMergeTol) continue;
      double lo = std::min(a.x(), b.x()) - kMergeTol, hi = std::max(a.x(), b.x()) + kMergeTol;
      auto it = std::lower_bound(verts.begin(), verts.end(), lo,
                                 [](const Vec3& p, double x) { return p.x() < x; });
      std::vector<std::pair<double, Vec3>> inner;
      for (; it != verts.end() && it->x() <= hi; ++it) {
        double t = (*it - a).dot(d) / len2;
        if (t <= 0 || t >= 1) continue;
        if ((*it - a).norm() < kMergeTol || (*it - b).norm() < kMergeTol) continue;
        if ((a + t * d - *it).norm() < kMergeTol) inner.push_back({t, *it});
      }
      std::sort(inner.begin(), inner.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
      for (const auto& [t, p] : inner)
        if ((p - out.back()).norm() >= kMergeTol) out.push_back(p);
    }
    return out;
  };
  std::vector<Face> out;
  for (const auto& f : shell) {
    Face g{split(f.ring), {}};
    for (const auto& h : f.holes) g.holes.push_back(split(h));
    out.push_back(std::move(g));
  }
  return out;
}

using Soup = std::vector<std::vector<std::size_t>>;

// Edge-use counts of the triangle soup: closedness, manifold edges, and whether
// each edge is walked once in each direction (consistent orientation).
void check_edges(const Soup& tris, Problems& pr) {
  std::map<std::pair<size_t, size_t>, std::array<int, 2>> uses;  // (lo, hi) -> {lo->hi, hi->lo}
  for (const auto& t : tris)
    for (int k = 0; k < 3; ++k) {
      size_t a = t[k], b = t[(k + 1) % 3];
      if (a < b) ++uses[{a, b}][0];
      else ++uses[{b, a}][1];
    }
  int open = 0, nonmanifold = 0, flipped = 0;
  for (const auto& [e, c] : uses) {
    int sum = c[0] + c[1];
    if (sum == 1) ++open;
    else if (sum > 2) ++nonmanifold;
    else if (c[0] != 1) ++flipped;
  }
  if (open) pr.add("not_closed", std::to_string(open) + " boundary edges");
  if (nonmanifold) pr.add("non_manifold", std::to_string(nonmanifold) + " edges shared by more than two faces");
  if (flipped) pr.add("inconsistent_orientation", std::to_string(flipped) + " edges walked twice in the same direction (a flipped face)");
}

// A vertex lying on the inside of a triangle it is not a corner of: two faces
// touch there without sharing an edge (a step wall's foot on the wall beside
// it). CGAL's test misses such contact when it is off by a hair; `validate`,
// which snaps vertices, reports it as a self-intersection.
constexpr double kTouchTol = 1e-3;  // validate's vertex snap

bool vertex_inside_a_face(const std::vector<Vec3>& pts, const Soup& tris) {
  for (const auto& t : tris) {
    const Vec3 &a = pts[t[0]], &b = pts[t[1]], &c = pts[t[2]];
    const Vec3 n = (b - a).cross(c - a);
    const double twice_area = n.norm();
    if (twice_area < 1e-12) continue;
    const Vec3 lo = a.cwiseMin(b).cwiseMin(c).array() - kTouchTol, hi = a.cwiseMax(b).cwiseMax(c).array() + kTouchTol;
    for (size_t v = 0; v < pts.size(); ++v) {
      if (v == t[0] || v == t[1] || v == t[2]) continue;
      const Vec3& q = pts[v];
      if ((q.array() < lo.array()).any() || (q.array() > hi.array()).any()) continue;
      if (std::abs(n.dot(q - a)) / twice_area >= kTouchTol) continue;
      // Twice the areas of the sub-triangles: over each edge's length, q's distance inside it.
      const double da = n.dot((c - b).cross(q - b)) / twice_area, db = n.dot((a - c).cross(q - c)) / twice_area,
                   dc = n.dot((b - a).cross(q - a)) / twice_area;
      if (da / (c - b).norm() > kTouchTol && db / (a - c).norm() > kTouchTol && dc / (b - a).norm() > kTouchTol)
        return true;
    }
  }
  return false;
}

}  // namespace

bool tilted_triangle(const Face& face, double tol_deg) {
  const double cos_tol = std::cos(tol_deg * M_PI / 180);
  std::vector<Vec3> normals;
  for (const auto& t : triangulate(face)) {
    const Vec3 tn = (t.b - t.a).cross(t.c - t.a);
    if (tn.norm() < 1e-12) continue;
    normals.push_back(tn.normalized());
  }
  for (size_t i = 0; i < normals.size(); ++i)
    for (size_t j = i + 1; j < normals.size(); ++j)
      if (normals[i].dot(normals[j]) < cos_tol) return true;
  return false;
}

SolidCheck check_solid(const std::vector<Face>& shell, double planarity_tol) {
  SolidCheck r;
  Problems pr;
  if (shell.empty()) pr.add("empty", "no faces");
  check_faces(shell, planarity_tol, pr);

  // Triangle soup with merged vertices.
  VertexPool pool;
  Soup tris;
  for (const auto& f : split_t_junctions(shell)) {
    for (const auto& t : triangulate(f)) {
      std::vector<size_t> tri{pool.index(t.a), pool.index(t.b), pool.index(t.c)};
      if (tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2]) continue;
      r.area += 0.5 * (t.b - t.a).cross(t.c - t.a).norm();
      tris.push_back(std::move(tri));
    }
  }
  std::vector<K::Point_3> pts;
  for (const auto& p : pool.points) pts.emplace_back(p.x(), p.y(), p.z());

  if (!tris.empty()) {
    check_edges(tris, pr);
    CGAL::Surface_mesh<K::Point_3> mesh;
    bool as_given = PMP::is_polygon_soup_a_polygon_mesh(tris);
    if (as_given) {
      PMP::polygon_soup_to_polygon_mesh(pts, tris, mesh);
    } else {
      // Orientable fix-up only to look for self-intersections; it duplicates
      // pinched vertices, which is what "non-manifold" means here.
      auto p2 = pts;
      auto t2 = tris;
      PMP::orient_polygon_soup(p2, t2);
      if (p2.size() > pts.size()) pr.add("non_manifold", std::to_string(p2.size() - pts.size()) + " pinched vertices");
      PMP::polygon_soup_to_polygon_mesh(p2, t2, mesh);
    }
    if (PMP::does_self_intersect(mesh)) pr.add("self_intersection", "faces cross each other");
    else if (vertex_inside_a_face(pool.points, tris)) pr.add("self_intersection", "a corner touches the inside of another face");
    if (as_given && CGAL::is_closed(mesh)) {
      if (!PMP::is_outward_oriented(mesh)) pr.add("inward_orientation", "the shell is inside out");
      r.volume = PMP::volume(mesh);
      if (!(r.volume > 0)) pr.add("non_positive_volume", "volume " + fmt(r.volume) + " m3");
    }
  }
  r.problems = pr.list();
  r.ok = std::none_of(r.problems.begin(), r.problems.end(),
                      [](const SolidProblem& p) { return !p.warning; });
  return r;
}

}  // namespace c3d

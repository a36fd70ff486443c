#include "core/mesh/simplify.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/Constrained_placement.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/Count_stop_predicate.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/GarlandHeckbert_plane_policies.h>
#include <CGAL/Surface_mesh_simplification/Policies/Edge_collapse/LindstromTurk_cost.h>
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
#include <map>
#include <functional>
#include <set>
#include <stdexcept>

#include "core/mesh/open3d_mesh.h"
#include "core/mesh/spacing.h"

namespace c3d {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Mesh = CGAL::Surface_mesh<Point>;
namespace SMS = CGAL::Surface_mesh_simplification;
namespace PMP = CGAL::Polygon_mesh_processing;
using Triangle = Kernel::Triangle_3;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, CGAL::AABB_triangle_primitive<Kernel, std::vector<Triangle>::const_iterator>>>;

// The mesh's triangles in CGAL's form, degenerate ones left out, with the
// index of the face each came from.
struct Triangles {
  std::vector<Triangle> all;
  std::vector<size_t> face;
};
Triangles triangles_of(const TriMesh& mesh) {
  Triangles out;
  const auto corners = mesh.soup();
  for (size_t f = 0; f < corners.size(); ++f) {
    const auto& c = corners[f];
    const Triangle t(Point(c[0].x(), c[0].y(), c[0].z()), Point(c[1].x(), c[1].y(), c[1].z()),
                     Point(c[2].x(), c[2].y(), c[2].z()));
    if (t.is_degenerate()) continue;
    out.all.push_back(t);
    out.face.push_back(f);
  }
  return out;
}

// The mesh as it came, each face in its region (-1 where none is given).
Simplified unchanged(const TriMesh& mesh, const MeshRegions& regions) {
  Simplified same{without_loose_vertices(mesh), regions.face_region};
  same.face_region.resize(mesh.triangles.size(), -1);
  return same;
}

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

using Region = Mesh::Property_map<Mesh::Face_index, int>;

// The mesh back as plain data, with each face's region.
Simplified from_surface_mesh(Mesh& m, const Region& region) {
  m.collect_garbage();
  Simplified out;
  for (auto v : m.vertices()) {
    const Point& p = m.point(v);
    out.mesh.vertices.emplace_back(p.x(), p.y(), p.z());
  }
  for (auto f : m.faces()) {
    std::array<int, 3> t{};
    int k = 0;
    for (auto v : CGAL::vertices_around_face(m.halfedge(f), m))
      if (k < 3) t[size_t(k++)] = int(v.idx());
    if (k != 3) continue;
    out.mesh.triangles.push_back(t);
    out.face_region.push_back(region[f]);
  }
  return out;
}

// A face by its corners' places, sorted: the soup repair renumbers vertices
// and may reorder faces, but keeps where their corners are.
using Place = std::array<double, 3>;
using FaceKey = std::array<Place, 3>;
template <typename P>
Place place_of(const P& p) { return {p[0], p[1], p[2]}; }
template <typename P>
FaceKey key_of(const P& a, const P& b, const P& c) {
  FaceKey k = {place_of(a), place_of(b), place_of(c)};
  std::sort(k.begin(), k.end());
  return k;
}

// Each face of `m` gets the region its twin in `t` had (-1: none, or a face
// the repair or a hole fill made, which then takes a neighbour's region).
Region carry_regions(Mesh& m, const TriMesh& t, const std::vector<int>& face_region) {
  Region region = m.add_property_map<Mesh::Face_index, int>("f:region", -1).first;
  if (face_region.size() != t.triangles.size()) return region;
  std::map<FaceKey, int> of;
  for (size_t f = 0; f < t.triangles.size(); ++f) {
    const auto& c = t.triangles[f];
    of[key_of(t.vertices[size_t(c[0])], t.vertices[size_t(c[1])], t.vertices[size_t(c[2])])] = face_region[f];
  }
  for (auto f : m.faces()) {
    std::vector<Point> c;
    for (auto v : CGAL::vertices_around_face(m.halfedge(f), m)) c.push_back(m.point(v));
    if (c.size() != 3) continue;
    const auto it = of.find(key_of(c[0], c[1], c[2]));
    if (it != of.end()) region[f] = it->second;
  }
  return region;
}

// A face without a region (a hole fill, or a face the repair made) takes a
// neighbour's region whose faces already touch all its corners, until none
// can: a sampling gap inside a region, or at its edge, becomes its own; one
// where regions meet keeps no region, and so no region grows across it
// (stage one keeps its borders as another region's).
void fill_unlabelled(Mesh& m, Region& region) {
  const auto touches = [&](Mesh::Vertex_index v, int r) {
    for (auto h : CGAL::halfedges_around_target(v, m))
      if (m.face(h) != Mesh::null_face() && region[m.face(h)] == r) return true;
    return false;
  };
  for (bool changed = true; changed;) {
    changed = false;
    for (auto f : m.faces()) {
      if (region[f] >= 0) continue;
      for (auto h : CGAL::halfedges_around_face(m.halfedge(f), m)) {
        const auto g = m.face(m.opposite(h));
        if (g == Mesh::null_face() || region[g] < 0) continue;
        bool all = true;
        for (auto v : CGAL::vertices_around_face(m.halfedge(f), m)) all = all && touches(v, region[g]);
        if (!all) continue;
        region[f] = region[g], changed = true;
        break;
      }
    }
  }
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

// Stage one's stop per region: each region's live faces and the count it
// may collapse down to.
struct RegionTargets {
  Region region;
  std::vector<long> faces, target;
};

// The safe filter, then the region's target: a collapse that would take its
// region under its target is refused (stage one keeps the regions' borders,
// so both faces an edge collapse removes lie in one region).
struct Filter {
  SafeFilter safe;
  RegionTargets* targets = nullptr;
  template <typename Profile>
  boost::optional<typename Profile::Point> operator()(const Profile& p,
                                                      boost::optional<typename Profile::Point> placed) const {
    placed = safe(p, placed);
    if (!placed || !targets) return placed;
    const Mesh& m = p.surface_mesh();
    const int r = targets->region[m.face(p.is_v0_v1_a_border() ? p.v1_v0() : p.v0_v1())];
    if (r < 0) return placed;
    const long removed = long(!p.is_v0_v1_a_border()) + long(!p.is_v1_v0_a_border());
    if (targets->faces[size_t(r)] - removed < targets->target[size_t(r)]) return boost::none;
    targets->faces[size_t(r)] -= removed;
    return placed;
  }
};

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

// Edge collapse until at most `faces` faces remain, by the cost and the
// placement given; edges `fixed` says are not collapsed and their vertices
// stay. No collapse turns a face's normal over (CGAL's bounded normal change)
// or puts its vertex far from the mesh it started from (NearTheStart).
// CGAL collapses no edge whose two vertices both touch fixed edges; the
// placement keeps a vertex that touches one where it is, unless `placement`
// keeps its own vertices (`Keeps`).
template <bool Keeps = false, typename Cost, typename Placement, typename Fixed>
void collapse(Mesh& m, size_t faces, const Cost& cost, const Placement& placement, const Filter& filter, Fixed fixed) {
  auto constrained = m.add_property_map<Mesh::Edge_index, bool>("e:constrained", false).first;
  for (auto e : m.edges()) constrained[e] = fixed(e);
  const SMS::Count_stop_predicate<Mesh> stop(faces * 3 / 2);
  const auto with = CGAL::parameters::get_cost(cost).edge_is_constrained_map(constrained).filter(filter);
  if constexpr (Keeps) {
    SMS::edge_collapse(m, stop, with.get_placement(placement));
  } else {
    const SMS::Constrained_placement<Placement, decltype(constrained)> kept(constrained, placement);
    SMS::edge_collapse(m, stop, with.get_placement(kept));
  }
  m.remove_property_map(constrained);
  m.collect_garbage();
}

void collapse_lindstrom_turk(Mesh& m, size_t faces, const Filter& filter, std::function<bool(Mesh::Edge_index)> fixed) {
  collapse(m, faces, SMS::LindstromTurk_cost<Mesh>(), SMS::LindstromTurk_placement<Mesh>(), filter, fixed);
}

// Each region's target: its faces times its kind's weight times one share,
// the largest share whose targets fit the budget (at most all its faces).
std::vector<long> region_targets(const std::vector<long>& faces, const std::vector<RegionKind>& kinds, size_t budget,
                                 const RegionRetention& w) {
  const auto at = [&](double share) {
    std::vector<long> t(faces.size());
    long sum = 0;
    for (size_t r = 0; r < faces.size(); ++r) {
      const double weight = kinds[r] == RegionKind::Planar ? w.planar : kinds[r] == RegionKind::Curved ? w.curved : w.detail;
      t[r] = std::min(faces[r], long(std::ceil(weight * share * double(faces[r]))));
      sum += t[r];
    }
    return std::pair{t, sum};
  };
  double lo = 0, hi = 1;
  for (int k = 0; k < 50; ++k) {
    const double mid = (lo + hi) / 2;
    (at(mid).second <= long(budget) ? lo : hi) = mid;
  }
  return at(lo).first;
}

// How many regions meet at a vertex, the open border counted as one.
int regions_at(const Mesh& m, Mesh::Vertex_index v, const Region& region) {
  std::array<int, 8> seen{};
  int n = 0;
  for (auto h : CGAL::halfedges_around_target(v, m)) {
    const auto f = m.face(h);
    const int r = f == Mesh::null_face() ? -2 : region[f];
    if (std::find(seen.begin(), seen.begin() + n, r) == seen.begin() + n && n < int(seen.size())) seen[size_t(n++)] = r;
  }
  return n;
}

// Places no collapse removes or moves (a planar region's extremes, from the
// mesh as it came): both stages keep them, so each planar region keeps its
// extent (seed 002's measure), where a noisy border's outermost zigzag, or a
// sampling gap's border once filled, would otherwise go first. Held by place:
// a collapse may keep either vertex's index at the place it keeps.
struct Anchors {
  std::set<Place> at;
  bool operator()(const Mesh& m, Mesh::Vertex_index v) const { return at.count(place_of(m.point(v))) > 0; }
};
Anchors anchors_at(const std::vector<Vec3>& places) {
  Anchors a;
  for (const Vec3& p : places) a.at.insert(place_of(p));
  return a;
}

// The edge's end whose keeping costs less: the other vertex goes to it.
template <typename Cost, typename Profile>
typename Profile::Point cheaper_end(const Cost& cost, const Profile& p) {
  const auto c0 = cost(p, boost::optional<Point>(p.p0())), c1 = cost(p, boost::optional<Point>(p.p1()));
  return c0 && (!c1 || *c0 <= *c1) ? p.p0() : p.p1();
}

// Stage one's placement: inside a planar region the edge's cheaper vertex
// stays where it is (a plane needs no new vertices, and the level's plane
// is then a subset of level 4's: an optimal placement near its border could
// land past it, widening the region); elsewhere Lindstrom and Turk's.
struct OnPlanesAVertex {
  Region region;
  const std::vector<RegionKind>* kinds = nullptr;
  SMS::LindstromTurk_placement<Mesh> free;
  SMS::LindstromTurk_cost<Mesh> cost;
  template <typename Profile>
  boost::optional<typename Profile::Point> operator()(const Profile& p) const {
    const Mesh& m = p.surface_mesh();
    const auto f = m.face(p.v0_v1()), g = m.face(m.opposite(p.v0_v1()));
    const int r = f != Mesh::null_face() ? region[f] : g != Mesh::null_face() ? region[g] : -1;
    if (r < 0 || size_t(r) >= kinds->size() || (*kinds)[size_t(r)] != RegionKind::Planar) return free(p);
    return cheaper_end(cost, p);
  }
};

// Stage two's placement: a vertex on a region's border or on the open border
// stays, unless the edge runs along that border: then the border gives up
// one of the edge's two vertices (the one whose removal costs less; never a
// corner, where three regions, or two and the open border, meet, nor a
// planar region's extreme). The kept border is a subset of the dense
// border's vertices: a straight frame or eave stays straight, and no wall is
// pulled up from its bottom edge.
struct AlongBorders {
  Region region;
  const Anchors* anchor = nullptr;
  SMS::LindstromTurk_placement<Mesh> free;
  SMS::LindstromTurk_cost<Mesh> cost;
  template <typename Profile>
  boost::optional<typename Profile::Point> operator()(const Profile& p) const {
    const Mesh& m = p.surface_mesh();
    const int n0 = (*anchor)(m, p.v0()) ? 3 : regions_at(m, p.v0(), region);
    const int n1 = (*anchor)(m, p.v1()) ? 3 : regions_at(m, p.v1(), region);
    const auto h = p.v0_v1();
    const auto region_of = [&](Mesh::Face_index f) { return f == Mesh::null_face() ? -2 : region[f]; };
    if (region_of(m.face(h)) != region_of(m.face(m.opposite(h)))) {
      if (n0 >= 3 && n1 >= 3) return boost::none;
      if (n0 >= 3) return p.p0();
      if (n1 >= 3) return p.p1();
      return cheaper_end(cost, p);
    }
    if (n0 >= 2 && n1 >= 2) return boost::none;
    if (n0 >= 2) return p.p0();
    if (n1 >= 2) return p.p1();
    return free(p);
  }
};

// Seed 002's two stages. One: inside the regions down to their targets, the
// regions' borders and the open border kept. Two, where that leaves more than
// the budget: the borders give up vertices along themselves (AlongBorders).
// Where the corners of many small regions still hold more, the level stays
// above its budget: plain collapse past them folded a roof's plane over its
// ridge and pulled faces metres off their planes (docs/meshes.md).
void collapse_boundary_aware(Mesh& m, size_t faces, const SafeFilter& safe, Region& region, const Anchors& anchor,
                             const MeshRegions& regions, const RegionRetention& retention) {
  RegionTargets targets{region, std::vector<long>(regions.kinds.size(), 0), {}};
  for (auto f : m.faces())
    if (region[f] >= 0 && size_t(region[f]) < targets.faces.size()) ++targets.faces[size_t(region[f])];
  targets.target = region_targets(targets.faces, regions.kinds, faces, retention);
  const auto region_border = [&](Mesh::Edge_index e) {
    const auto h = m.halfedge(e);
    return m.is_border(e) || region[m.face(h)] != region[m.face(m.opposite(h))] || anchor(m, m.source(h)) ||
           anchor(m, m.target(h));
  };
  collapse(m, faces, SMS::LindstromTurk_cost<Mesh>(), OnPlanesAVertex{region, &regions.kinds, {}, {}},
           Filter{safe, &targets}, region_border);
  if (size_t(m.number_of_faces()) > faces)
    collapse<true>(m, faces, SMS::LindstromTurk_cost<Mesh>(), AlongBorders{region, &anchor, {}, {}},
                   Filter{safe, nullptr}, [](Mesh::Edge_index) { return false; });
}

// Garland and Heckbert's plane quadrics, in one stage, the open border kept.
void collapse_garland_heckbert(Mesh& m, size_t faces, const SafeFilter& safe) {
  const SMS::GarlandHeckbert_plane_policies<Mesh, Kernel> policies(m);
  collapse(m, faces, policies.get_cost(), policies.get_placement(), Filter{safe, nullptr},
           [&](Mesh::Edge_index e) { return m.is_border(e); });
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

const char* simplifier_name(Simplifier s) {
  switch (s) {
    case Simplifier::BoundaryAware: return "boundary";
    case Simplifier::LindstromTurk: return "qem";
    case Simplifier::GarlandHeckbert: return "garland";
    case Simplifier::VertexClustering: return "clustering";
  }
  return "?";
}

Simplifier simplifier_named(const std::string& name) {
  for (Simplifier s : {Simplifier::BoundaryAware, Simplifier::LindstromTurk, Simplifier::GarlandHeckbert,
                       Simplifier::VertexClustering})
    if (name == simplifier_name(s)) return s;
  throw std::invalid_argument("unknown simplification '" + name + "' (boundary, qem, garland, clustering)");
}

namespace {

// Where the faces of `light` lie in `dense`'s regions: the region of the
// dense face nearest each light face's centre (vertex clustering keeps no
// face, so none carries its region).
std::vector<int> nearest_regions(const TriMesh& light, const TriMesh& dense, const std::vector<int>& face_region) {
  const Triangles triangles = triangles_of(dense);
  std::vector<int> out(light.triangles.size(), -1);
  if (triangles.all.empty() || face_region.size() != dense.triangles.size()) return out;
  Tree tree(triangles.all.begin(), triangles.all.end());
  tree.accelerate_distance_queries();
  const auto corners = light.soup();
  for (size_t f = 0; f < corners.size(); ++f) {
    const Vec3 c = (corners[f][0] + corners[f][1] + corners[f][2]) / 3;
    const auto nearest = tree.closest_point_and_primitive(Point(c.x(), c.y(), c.z())).second;
    out[f] = face_region[triangles.face[size_t(nearest - triangles.all.begin())]];
  }
  return out;
}

// Vertex clustering at the smallest cell (halving the bracket 20 times) whose
// mesh has at most `faces` faces.
TriMesh clustered(const TriMesh& mesh, size_t faces) {
  double lo = 0, hi = 1e-3;
  TriMesh best = vertex_clustering(mesh, hi);
  while (best.triangles.size() > faces && hi < 1e4) lo = hi, hi *= 2, best = vertex_clustering(mesh, hi);
  for (int k = 0; k < 20; ++k) {
    const double mid = (lo + hi) / 2;
    TriMesh m = vertex_clustering(mesh, mid);
    if (m.triangles.size() <= faces) hi = mid, best = std::move(m);
    else lo = mid;
  }
  return best;
}

}  // namespace

Simplified simplified(const TriMesh& mesh, size_t faces, double small_hole, double reach, const MeshRegions& regions,
                      Simplifier how, const RegionRetention& retention) {
  if (mesh.triangles.size() <= faces) return unchanged(mesh, regions);
  if (how == Simplifier::VertexClustering) {
    Simplified out{clustered(mesh, faces), {}};
    out.face_region = nearest_regions(out.mesh, mesh, regions.face_region);
    return out;
  }
  const Triangles start = triangles_of(mesh);
  Tree tree(start.all.begin(), start.all.end());
  tree.accelerate_distance_queries();
  const SafeFilter safe(NearTheStart{&tree, reach});
  Mesh m = to_surface_mesh(mesh);
  Region region = carry_regions(m, mesh, regions.face_region);
  fill_small_holes(m, small_hole);
  fill_unlabelled(m, region);
  const auto border = [&](Mesh::Edge_index e) { return m.is_border(e); };
  switch (how) {
    case Simplifier::BoundaryAware:
      collapse_boundary_aware(m, faces, safe, region,
                              anchors_at(regions.extremes.empty() ? planar_extremes(mesh, regions) : regions.extremes),
                              regions, retention);
      break;
    case Simplifier::LindstromTurk: collapse_lindstrom_turk(m, faces, Filter{safe, nullptr}, border); break;
    case Simplifier::GarlandHeckbert: collapse_garland_heckbert(m, faces, safe); break;
    case Simplifier::VertexClustering: break;
  }
  Simplified out = from_surface_mesh(m, region);
  // A soup that is no 2-manifold (an alpha shape's slabs) comes apart in
  // sheets whose hole fills can outweigh what the collapse removed: then the
  // mesh as it came is the lighter one.
  if (out.mesh.triangles.size() >= mesh.triangles.size()) return unchanged(mesh, regions);
  TriMesh compact = without_loose_vertices(out.mesh);
  out.mesh = std::move(compact);
  return out;
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
    const Region none = wrap.add_property_map<Mesh::Face_index, int>("f:region", -1).first;
    out = {from_surface_mesh(wrap, none).mesh, alpha, alpha / 30};
    if (out.mesh.triangles.size() <= max_faces || alpha > size.norm()) break;
  }
  return out;
}

}  // namespace c3d

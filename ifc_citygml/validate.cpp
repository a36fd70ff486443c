// Solid and polygon validation after ISO 19107 as val3dity applies it: rings
// (101-104), polygons (203, 204), then the shell (301-307). Vertices closer than
// snap_tol are one vertex, as in val3dity.
#include "ifc_citygml/validate.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <set>
#include <numeric>
#include <sstream>

#include "core/geometry/geometry.h"
#include "core/check/solid_check.h"
#include "ifc_citygml/detail.h"

namespace c3d {

const char* val3dity_name(int code) {
  switch (code) {
    case 101: return "TOO_FEW_POINTS";
    case 102: return "CONSECUTIVE_POINTS_SAME";
    case 104: return "RING_SELF_INTERSECTION";
    case 203: return "NON_PLANAR_POLYGON_DISTANCE_PLANE";
    case 204: return "NON_PLANAR_POLYGON_NORMALS_DEVIATION";
    case 301: return "TOO_FEW_POLYGONS";
    case 302: return "SHELL_NOT_CLOSED";
    case 303: return "NON_MANIFOLD_CASE";
    case 305: return "MULTIPLE_CONNECTED_COMPONENTS";
    case 306: return "SHELL_SELF_INTERSECTION";
    case 307: return "POLYGON_WRONG_ORIENTATION";
  }
  return "UNKNOWN";
}

std::string to_string(const ValidationIssue& i) {
  std::ostringstream os;
  os << i.building_id << ": " << i.code << ' ' << val3dity_name(i.code) << " at " << i.where;
  if (!i.message.empty()) os << ": " << i.message;
  return os.str();
}

namespace {

using Ids = std::vector<int>;

struct Checker {
  const Building& b;
  const ValidationOptions& opt;
  std::vector<ValidationIssue> issues;

  void report(int code, const std::string& where, const std::string& msg) {
    issues.push_back({b.id, code, where, msg});
  }

  // Ring and polygon rules (core/polygon_rules); false when the polygon is unusable.
  bool polygon(const Face& f, VertexSnap& snap, const std::string& where, std::vector<Ids>* rings) {
    std::vector<PolygonIssue> found;
    const bool ok = check_polygon(f, opt, snap, *rings, found);
    for (const auto& i : found) report(i.code, where + i.where, i.message);
    return ok;
  }

  void elements() {
    for (size_t e = 0; e < b.elements.size(); ++e)
      for (size_t k = 0; k < b.elements[e].faces.size(); ++k) {
        VertexSnap snap(opt.snap_tol);
        std::vector<Ids> rings;
        polygon(b.elements[e].faces[k], snap,
                "element " + std::to_string(e) + " (" + to_string(b.elements[e].type) + ") face " +
                    std::to_string(k),
                &rings);
      }
  }

  struct Use { int face; bool forward; };

  // The shell being checked (the solid, or a lower LoD's) and its name in reports.
  const std::vector<Face>* solid = nullptr;
  std::string name = "solid";

  void shell(const std::vector<Face>& faces_in, const std::string& shell_name) {
    solid = &faces_in;
    name = shell_name;
    if (solid->size() < 4) {
      report(kTooFewPolygons, name, std::to_string(solid->size()) + " faces");
      return;
    }
    VertexSnap snap(opt.snap_tol);
    std::vector<std::vector<Ids>> faces(solid->size());
    bool polygons_ok = true;
    for (size_t f = 0; f < solid->size(); ++f)
      polygons_ok &= polygon((*solid)[f], snap, name + " face " + std::to_string(f), &faces[f]);
    if (!polygons_ok) return;  // val3dity stops at the first level with errors

    std::map<std::pair<int, int>, std::vector<Use>> edges;
    for (size_t f = 0; f < faces.size(); ++f)
      for (const auto& r : faces[f])
        for (size_t i = 0; i < r.size(); ++i) {
          int a = r[i], c = r[(i + 1) % r.size()];
          edges[{std::min(a, c), std::max(a, c)}].push_back({int(f), a < c});
        }
    if (!edge_rules(edges)) return;
    if (!vertex_rules(faces, snap.points)) return;
    if (components(faces, edges) > 1) {
      report(kMultipleConnectedComponents, name, "shell falls apart into several pieces");
      return;
    }
    if (signed_volume() <= 0) {
      report(kPolygonWrongOrientation, name, "all faces point inward (negative volume)");
      return;
    }
    self_intersection(faces, snap);
  }

  bool edge_rules(const std::map<std::pair<int, int>, std::vector<Use>>& edges) {
    int open = 0, nonmanifold = 0;
    std::vector<int> flipped;
    for (const auto& [e, uses] : edges) {
      if (uses.size() == 1) ++open;
      else if (uses.size() > 2) ++nonmanifold;
      else if (uses[0].forward == uses[1].forward)
        flipped.push_back(uses[0].face), flipped.push_back(uses[1].face);
    }
    if (open) report(kShellNotClosed, name, std::to_string(open) + " edges used by one face only");
    if (nonmanifold)
      report(kNonManifoldCase, name, std::to_string(nonmanifold) + " edges used by more than two faces");
    if (!open && !nonmanifold && !flipped.empty()) {
      // The face that disagrees with most of its neighbours is the flipped one.
      std::map<int, int> votes;
      for (int f : flipped) ++votes[f];
      auto worst = std::max_element(votes.begin(), votes.end(),
                                    [](auto& x, auto& y) { return x.second < y.second; });
      report(kPolygonWrongOrientation, name + " face " + std::to_string(worst->first),
             "face orientation disagrees with its neighbours");
    }
    return !open && !nonmanifold && flipped.empty();
  }

  // Around each vertex the faces must form one fan (no "two cones touching at
  // a tip"). Fans joined through one face count as one: a hole touching its
  // polygon's outer ring at a vertex (valid for OGC and val3dity) gives that
  // face two corners there (AHN3 09395's roof).
  bool vertex_rules(const std::vector<std::vector<Ids>>& faces, const std::vector<Vec3>& points) {
    struct Corner {
      int next, face;
    };
    std::vector<std::map<int, Corner>> at(points.size());  // at vertex v: prev neighbour -> corner
    for (size_t f = 0; f < faces.size(); ++f)
      for (const auto& r : faces[f])
        for (size_t i = 0; i < r.size(); ++i)
          at[r[i]][r[(i + r.size() - 1) % r.size()]] = {r[(i + 1) % r.size()], int(f)};
    for (size_t v = 0; v < points.size(); ++v) {
      if (at[v].empty() || one_fan(at[v])) continue;
      char where[96];
      std::snprintf(where, sizeof where, " vertex (%.3f %.3f %.3f)", points[v].x(), points[v].y(), points[v].z());
      report(kNonManifoldCase, name + where, "faces around the vertex do not form one fan");
      return false;
    }
    return true;
  }

  // Whether the corners at one vertex (prev -> {next, face}) close into fans
  // that share faces, so that they are one.
  template <class Corners>
  static bool one_fan(const Corners& corners) {
    for (const auto& [prev, c] : corners)  // an open fan: not a closed shell here
      if (!corners.count(c.next)) return false;
    std::map<int, int> fan_of_face;  // face -> the fan it was first met in
    std::vector<int> joined;         // per fan: the fan it joins (union-find)
    auto root = [&](int k) {
      while (joined[size_t(k)] != k) k = joined[size_t(k)];
      return k;
    };
    std::set<int> walked;
    for (const auto& [first, unused] : corners) {
      if (walked.count(first)) continue;
      const int fan = int(joined.size());
      joined.push_back(fan);
      for (int cur = first; walked.insert(cur).second;) {
        const auto& c = corners.at(cur);
        auto [it, fresh] = fan_of_face.try_emplace(c.face, fan);
        if (!fresh) joined[size_t(root(fan))] = root(it->second);
        cur = c.next;
      }
    }
    int fans = 0;
    for (size_t k = 0; k < joined.size(); ++k) fans += root(int(k)) == int(k);
    return fans == 1;
  }

  int components(const std::vector<std::vector<Ids>>& faces,
                 const std::map<std::pair<int, int>, std::vector<Use>>& edges) {
    std::vector<int> parent(faces.size());
    std::iota(parent.begin(), parent.end(), 0);
    std::function<int(int)> root = [&](int x) { return parent[x] == x ? x : parent[x] = root(parent[x]); };
    for (const auto& [e, uses] : edges)
      for (const auto& u : uses) parent[root(u.face)] = root(uses[0].face);
    int n = 0;
    for (size_t f = 0; f < faces.size(); ++f) n += root(int(f)) == int(f);
    return n;
  }

  double signed_volume() const {
    double v = 0;
    for (const auto& f : *solid) {
      v += f.ring.front().dot(newell_normal(f.ring)) / 6;
      for (const auto& h : f.holes) {
        Vec3 hn = newell_normal(h);
        if (hn.dot(newell_normal(f.ring)) > 0) hn = -hn;  // holes count negative
        v += h.front().dot(hn) / 6;
      }
    }
    return v;
  }

  void self_intersection(const std::vector<std::vector<Ids>>& faces, VertexSnap& snap) {
    using K = CGAL::Exact_predicates_inexact_constructions_kernel;
    using Mesh = CGAL::Surface_mesh<K::Point_3>;
    Mesh mesh;
    std::vector<Mesh::Vertex_index> vi;
    for (const auto& p : snap.points) vi.push_back(mesh.add_vertex(K::Point_3(p.x(), p.y(), p.z())));
    std::vector<size_t> solid_face;  // of each triangle
    for (size_t f = 0; f < solid->size(); ++f) {
      exp::Triangles t = exp::triangulate((*solid)[f]);
      Ids flat;
      for (const auto& r : faces[f]) flat.insert(flat.end(), r.begin(), r.end());
      if (t.points.size() != flat.size()) return;  // ring had repeats: skip this test
      for (const auto& tr : t.tris) {
        if (mesh.add_face(vi[flat[tr[0]]], vi[flat[tr[1]]], vi[flat[tr[2]]]) == Mesh::null_face())
          return;
        solid_face.push_back(f);
      }
    }
    std::vector<std::pair<Mesh::Face_index, Mesh::Face_index>> pairs;
    CGAL::Polygon_mesh_processing::self_intersections(mesh, std::back_inserter(pairs));
    if (pairs.empty()) return;
    size_t f1 = solid_face[size_t(pairs[0].first)], f2 = solid_face[size_t(pairs[0].second)];
    report(kShellSelfIntersection, name + " faces " + std::to_string(std::min(f1, f2)) + " and " +
                                       std::to_string(std::max(f1, f2)),
           "faces of the shell intersect");
  }
};

}  // namespace

std::vector<ValidationIssue> validate_building(const Building& b, const ValidationOptions& opt) {
  Checker c{b, opt, {}};
  c.elements();
  c.shell(b.solid, "solid");
  for (const auto& l : b.lower_lods) c.shell(l.faces, std::string("lod ") + to_string(l.lod) + " solid");
  return c.issues;
}

std::vector<ValidationIssue> validate_model(const BatchModel& model, const ValidationOptions& opt) {
  std::vector<ValidationIssue> all;
  for (const auto& r : model.results)
    for (const auto& b : r.buildings) {
      auto v = validate_building(b, opt);
      all.insert(all.end(), v.begin(), v.end());
    }
  return all;
}

}  // namespace c3d

#include "core/reconstruct/lod13/layer_solid.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <utility>

#include "core/geometry/geometry.h"
#include "core/geometry/polygon_ops.h"
#include "core/reconstruct/lod13/raster.h"

namespace c3d::lod13 {
namespace {

// The subdivision is snap-rounded to this grid: no vertex lies nearer an edge
// it is not on than half of it, so nothing in the shell is closer than the
// validators' 1 mm snap, and the outlines move by a centimetre at most.
constexpr double kGridM = 0.01;
// An edge of the subdivision lies on a footprint edge when both its ends lie
// this close to it (the rounding moves them by up to 0.71 grid steps).
constexpr double kOnEdgeM = 0.75 * kGridM;
// Pieces smaller than this are noding crumbs, not parts of a layer.
constexpr double kCrumbM2 = 1e-6;
// Vertices nearer than this are one: the validators snap at 1 mm, and the
// export rounds to it, so two such vertices would become one there anyway.
constexpr double kWeldM = 2e-3;

// The planar subdivision: vertices shared by index, pieces as rings of indices.
struct Subdivision {
  std::vector<Vec2> vertices;
  std::map<std::pair<long, long>, std::vector<int>> index;  // weld cells -> vertices
  struct Piece {
    std::vector<std::vector<int>> rings;  // outer counter-clockwise, then holes clockwise
    double z = 0;
    int layer = 0;
  };
  std::vector<Piece> pieces;
  std::map<std::pair<int, int>, int> edge_piece;  // directed edge (interior on its left) -> piece

  // The vertex at v: an earlier one within kWeldM, else a new one.
  int id(const Vec2& v) {
    const long cx = long(std::floor(v.x() / kWeldM)), cy = long(std::floor(v.y() / kWeldM));
    for (long dx = -1; dx <= 1; ++dx)
      for (long dy = -1; dy <= 1; ++dy) {
        auto it = index.find({cx + dx, cy + dy});
        if (it == index.end()) continue;
        for (int k : it->second)
          if ((vertices[size_t(k)] - v).norm() < kWeldM) return k;
      }
    index[{cx, cy}].push_back(int(vertices.size()));
    vertices.push_back(v);
    return int(vertices.size()) - 1;
  }
};

// The highest layer over point q: the last one holding it (children come after
// their parents, and siblings do not overlap); -1 off the footprint.
int layer_at(const std::vector<LayerPiece>& layers, const Vec2& q) {
  for (size_t k = layers.size(); k-- > 0;)
    if (in_polygon_plan(layers[k].outline, q)) return int(k);
  return -1;
}

// A ring as welded vertices, without repeats and without the spikes welding
// leaves (a -> b -> a).
std::vector<int> welded_ring(Subdivision& s, const Ring2& r) {
  std::vector<int> ids;
  for (const auto& v : r) {
    const int k = s.id(v);
    if (!ids.empty() && ids.back() == k) continue;
    if (ids.size() >= 2 && ids[ids.size() - 2] == k) {
      ids.pop_back();
      continue;
    }
    ids.push_back(k);
  }
  while (ids.size() >= 2 && ids.front() == ids.back()) ids.pop_back();
  while (ids.size() >= 3 && ids[1] == ids.back()) ids.erase(ids.begin()), ids.pop_back();
  return ids;
}

Subdivision subdivide(const std::vector<LayerPiece>& layers) {
  MultiPolygon2 outlines;
  for (const auto& l : layers) outlines.push_back(l.outline);
  Subdivision s;
  for (const Polygon2& p : poly::planar_faces(outlines, kGridM)) {
    if (area(p) < kCrumbM2) continue;
    const int k = layer_at(layers, poly::interior_point(p));
    if (k < 0) continue;  // a courtyard
    Subdivision::Piece piece;
    piece.z = layers[size_t(k)].z;
    piece.layer = k;
    std::vector<const Ring2*> rings{&p.outer};
    for (const auto& h : p.holes) rings.push_back(&h);
    for (const Ring2* r : rings) {
      const std::vector<int> ids = welded_ring(s, *r);
      if (ids.size() >= 3) piece.rings.push_back(ids);
      else if (r == &p.outer) piece.rings.clear();
      if (piece.rings.empty()) break;
    }
    if (piece.rings.empty()) continue;
    s.pieces.push_back(std::move(piece));
  }
  for (size_t f = 0; f < s.pieces.size(); ++f)
    for (const auto& r : s.pieces[f].rings)
      for (size_t i = 0; i < r.size(); ++i) s.edge_piece[{r[i], r[(i + 1) % r.size()]}] = int(f);
  return s;
}

double distance_to_segment(const Vec2& p, const Vec2& a, const Vec2& b) {
  const Vec2 d = b - a;
  const double t = std::clamp(d.dot(p - a) / std::max(d.squaredNorm(), 1e-300), 0.0, 1.0);
  return (a + t * d - p).norm();
}

bool on_party_edge(const Vec2& a, const Vec2& b, const Ring2& footprint, const std::vector<bool>& party) {
  for (size_t i = 0; i < footprint.size() && i < party.size(); ++i) {
    if (!party[i]) continue;
    const Vec2 &p = footprint[i], &q = footprint[(i + 1) % footprint.size()];
    if (distance_to_segment(a, p, q) < kOnEdgeM && distance_to_segment(b, p, q) < kOnEdgeM) return true;
  }
  return false;
}

Vec3 at(const Vec2& v, double z) { return {v.x(), v.y(), z}; }

// The wall under edge a -> b from `low` to `top`, facing right of a -> b,
// with every height of the corners' columns between the two on its sides.
Face wall(const Vec2& a, const Vec2& b, double low, double top, const std::set<double>& column_a,
          const std::set<double>& column_b) {
  Face f;
  f.ring = {at(a, low), at(b, low)};
  for (double z : column_b)
    if (z > low && z < top) f.ring.push_back(at(b, z));
  f.ring.push_back(at(b, top));
  f.ring.push_back(at(a, top));
  for (auto it = column_a.rbegin(); it != column_a.rend(); ++it)
    if (*it > low && *it < top) f.ring.push_back(at(a, *it));
  return f;
}

// The boundary edges (no piece on their right) chained into rings; a vertex
// with two boundary edges leaving it makes no ring (the outline pinches there).
bool chain_boundary(const std::vector<std::pair<int, int>>& edges, std::vector<std::vector<int>>& rings) {
  std::map<int, int> next;
  for (const auto& [a, b] : edges)
    if (!next.emplace(a, b).second) return false;
  while (!next.empty()) {
    const int start = next.begin()->first;
    std::vector<int> ring;
    int v = start;
    do {
      auto it = next.find(v);
      if (it == next.end()) return false;
      ring.push_back(v);
      v = it->second;
      next.erase(it);
    } while (v != start);
    rings.push_back(ring);
  }
  return true;
}

void add_walls(const Subdivision& s, double terrain_z, const Ring2& footprint, const std::vector<bool>& party,
               StackedSolid& out, std::vector<std::pair<int, int>>& boundary) {
  std::vector<std::set<double>> column(s.vertices.size());
  for (const auto& p : s.pieces)
    for (const auto& r : p.rings)
      for (int v : r) column[size_t(v)].insert(p.z);
  for (const auto& [e, f] : s.edge_piece)
    if (!s.edge_piece.count({e.second, e.first})) column[size_t(e.first)].insert(terrain_z);
  for (const auto& [e, f] : s.edge_piece) {
    const auto across = s.edge_piece.find({e.second, e.first});
    const bool outer = across == s.edge_piece.end();
    if (outer) boundary.push_back(e);
    const double top = s.pieces[size_t(f)].z, low = outer ? terrain_z : s.pieces[size_t(across->second)].z;
    if (top <= low) continue;  // the higher side builds it, or no step at all
    const Vec2 &a = s.vertices[size_t(e.first)], &b = s.vertices[size_t(e.second)];
    out.walls.push_back({wall(a, b, low, top, column[size_t(e.first)], column[size_t(e.second)]), outer,
                         outer && on_party_edge(a, b, footprint, party)});
  }
}

Ring3 ring_at(const Subdivision& s, const std::vector<int>& ids, double z, bool reverse) {
  Ring3 r;
  for (int v : ids) r.push_back(at(s.vertices[size_t(v)], z));
  if (reverse) std::reverse(r.begin(), r.end());
  return r;
}

}  // namespace

StackedSolid stacked_solid(const std::vector<LayerPiece>& layers, double terrain_z,
                           const std::vector<bool>& party_edge) {
  StackedSolid out;
  if (layers.empty() || layers[0].outline.outer.size() < 3) {
    out.problem = "no footprint";
    return out;
  }
  const Subdivision s = subdivide(layers);
  for (const auto& p : s.pieces) {
    if (!(p.z > terrain_z)) {
      out.problem = "a layer's top lies at or below the terrain";
      return out;
    }
    Face top{ring_at(s, p.rings[0], p.z, false), {}};
    for (size_t h = 1; h < p.rings.size(); ++h) top.holes.push_back(ring_at(s, p.rings[h], p.z, false));
    out.roofs.push_back(std::move(top));
    out.roof_layer.push_back(p.layer);
  }
  std::vector<std::pair<int, int>> boundary;
  add_walls(s, terrain_z, layers[0].outline.outer, party_edge, out, boundary);
  std::vector<std::vector<int>> rings;
  if (!chain_boundary(boundary, rings)) {
    out.problem = "the layers' outline touches itself at a vertex";
    return out;
  }
  std::vector<std::vector<int>> outers, holes;
  for (auto& r : rings) {
    Ring2 plan;
    for (int v : r) plan.push_back(s.vertices[size_t(v)]);
    (signed_area(plan) > 0 ? outers : holes).push_back(std::move(r));
  }
  if (outers.size() != 1) {
    out.problem = "the layers' footprint is not one polygon";
    return out;
  }
  out.ground.ring = ring_at(s, outers[0], terrain_z, true);
  for (const auto& h : holes) out.ground.holes.push_back(ring_at(s, h, terrain_z, true));
  return out;
}

std::vector<Face> shell_of(const StackedSolid& s) {
  std::vector<Face> shell{s.ground};
  for (const auto& w : s.walls) shell.push_back(w.face);
  shell.insert(shell.end(), s.roofs.begin(), s.roofs.end());
  return shell;
}

}  // namespace c3d::lod13

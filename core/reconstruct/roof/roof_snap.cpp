// Roof partition, second half: the regions' shared vertices snapped onto the
// lines and points where their planes meet, four-plane vertices split, and
// the seams that snapping disturbs settled.
#include <algorithm>
#include <cmath>
#include <map>
#include <optional>

#include "core/geometry/geometry.h"
#include "core/geometry/polygon_ops.h"
#include "core/geometry/welding.h"
#include "core/reconstruct/roof/roof.h"
#include "core/reconstruct/roof/roof_constants.h"
#include "core/reconstruct/roof/roof_snap.h"

namespace c3d {

using namespace roof;

namespace {

// Whether v lies on an edge of the outline; that edge's ends in a and b.
bool on_outline(const Polygon2& outline, const Vec2& v, Vec2& a, Vec2& b) {
  const Ring2& r = outline.outer;
  for (size_t i = 0; i < r.size(); ++i) {
    Vec2 p = r[i], q = r[(i + 1) % r.size()];
    Vec2 d = q - p;
    double t = (v - p).dot(d) / d.squaredNorm();
    if (t >= -1e-9 && t <= 1 + 1e-9 && (p + t * d - v).norm() < kOnOutlineTol) {
      a = p, b = q;
      return true;
    }
  }
  return false;
}

// One region's corner at a vertex: where its ring comes from and goes to.
struct Corner {
  int region;
  Ring2* ring;
  size_t at;
  Vec2 prev, next;
  bool ends_at(const Vec2& p) const { return prev == p || next == p; }
};

std::map<std::pair<double, double>, std::vector<Corner>> corners_by_vertex(std::vector<MultiPolygon2>& regions) {
  std::map<std::pair<double, double>, std::vector<Corner>> at;
  for (size_t r = 0; r < regions.size(); ++r)
    for (auto& p : regions[r]) {
      std::vector<Ring2*> rings{&p.outer};
      for (auto& h : p.holes) rings.push_back(&h);
      for (Ring2* ring : rings)
        for (size_t i = 0, n = ring->size(); i < n; ++i)
          at[{(*ring)[i].x(), (*ring)[i].y()}].push_back(
              Corner{int(r), ring, i, (*ring)[(i + n - 1) % n], (*ring)[(i + 1) % n]});
    }
  return at;
}

// The corners in their order round the vertex, each sharing an edge with the
// next; empty when they do not close one cycle of distinct regions.
std::vector<Corner> round_the_vertex(const std::vector<Corner>& corners) {
  std::vector<Corner> round{corners[0]};
  std::vector<bool> used(corners.size(), false);
  used[0] = true;
  Vec2 via = corners[0].next;
  while (round.size() < corners.size()) {
    size_t k = 1;
    while (k < corners.size() && (used[k] || !corners[k].ends_at(via))) ++k;
    if (k == corners.size()) return {};
    for (const Corner& c : round)
      if (c.region == corners[k].region) return {};
    used[k] = true;
    via = corners[k].prev == via ? corners[k].next : corners[k].prev;
    round.push_back(corners[k]);
  }
  return corners[0].ends_at(via) ? round : std::vector<Corner>{};
}

// The short ridge that replaces a vertex of four regions round it: on the line
// of the planes of corners `first` and first + 2, from the three-plane point
// with corner first + 1 (end1) to that with first + 3 (end3).
struct ShortRidge {
  size_t first;
  Vec2 end1, end3;
};

std::optional<ShortRidge> short_ridge(const std::vector<Corner>& round, const std::vector<Plane>& planes,
                                      const Vec2& v) {
  auto plane = [&](size_t k) { return planes[size_t(round[k % 4].region)]; };
  double zmin = 1e18, zmax = -1e18;
  for (size_t k = 0; k < 4; ++k) {
    const double z = plane(k).z_at(v.x(), v.y());
    zmin = std::min(zmin, z), zmax = std::max(zmax, z);
  }
  if (zmax - zmin < kOnePointGap || zmax - zmin > kMaxMeetHeightGap) return std::nullopt;  // one point, or a step
  auto toward = [&](size_t k) {  // into corner k's region: the mean direction of its two edges
    const Corner& c = round[k % 4];
    return Vec2((c.prev - v).normalized() + (c.next - v).normalized());
  };
  std::optional<ShortRidge> best;
  for (size_t s = 0; s < 2; ++s) {
    const auto p1 = common_point({plane(s), plane(s + 2), plane(s + 1)});
    const auto p3 = common_point({plane(s), plane(s + 2), plane(s + 3)});
    if (!p1 || !p3) continue;
    const ShortRidge r{s, p1->head<2>(), p3->head<2>()};
    const Vec2 d = r.end1 - r.end3;
    if (d.norm() < kMinShortRidge || (r.end1 - v).norm() > kMaxSnapMove || (r.end3 - v).norm() > kMaxSnapMove)
      continue;
    if (d.dot(toward(s + 1)) <= 0 || d.dot(toward(s + 3)) >= 0) continue;  // each end on its region's side
    if (!best || d.norm() < (best->end1 - best->end3).norm()) best = r;
  }
  return best;
}

}  // namespace

// Vertices shared by regions whose planes meet are moved onto the exact
// intersection (ridge line, or the point where three or more planes meet, least
// squares beyond three), so neighbouring faces agree in 3D, not just in plan.
void roof::snap_to_intersections(const Polygon2& outline, std::vector<MultiPolygon2>& regions,
                           const std::vector<Plane>& planes) {
  std::vector<Ring2*> rings;
  for (auto& r : regions)
    for (auto& p : r) {
      rings.push_back(&p.outer);
      for (auto& h : p.holes) rings.push_back(&h);
    }
  node_rings(rings, kNodeTol);
  std::map<std::pair<double, double>, std::vector<int>> users;
  for (size_t i = 0; i < regions.size(); ++i)
    for (auto& p : regions[i])
      for (auto& v : p.outer) {
        auto& u = users[{v.x(), v.y()}];
        if (std::find(u.begin(), u.end(), int(i)) == u.end()) u.push_back(int(i));
      }
  std::map<std::pair<double, double>, Vec2> moved;
  for (auto& [key, regs] : users) {
    if (regs.size() < 2) continue;
    Vec2 v(key.first, key.second), ea, eb;
    bool edge = on_outline(outline, v, ea, eb);
    double zmin = 1e18, zmax = -1e18;
    std::vector<Plane> ps;
    for (int r : regs) {
      double z = planes[r].z_at(v.x(), v.y());
      zmin = std::min(zmin, z), zmax = std::max(zmax, z);
      ps.push_back(planes[r]);
    }
    if (zmax - zmin > kMaxMeetHeightGap) continue;  // a step between roof levels: nothing to meet
    Vec2 target = v;
    if (ps.size() == 2) {
      auto line = intersect(ps[0], ps[1], kMinPlaneAngleDeg);
      if (!line || line->dir.head<2>().norm() < kMinPlanDir) continue;
      Vec2 p = line->point.head<2>(), d = line->dir.head<2>().normalized();
      if (edge) {
        auto x = intersect_lines(p, d, ea, (eb - ea).normalized());
        if (!x) continue;
        target = *x;
      } else {
        target = p + d * d.dot(v - p);
      }
    } else if (!edge) {
      auto cp = common_point(ps);
      if (!cp) continue;
      target = cp->head<2>();
    } else {
      continue;
    }
    if ((target - v).norm() < kMaxSnapMove) moved[key] = target;
  }
  for (auto* r : rings)
    for (auto& v : *r) {
      auto it = moved.find({v.x(), v.y()});
      if (it != moved.end()) v = it->second;
    }
  // Where four or more planes meet, vertices snapped to different triples of
  // them land millimetres apart; as separate vertices they would leave
  // slivers whose triangles tilt. They are one junction.
  node_rings(rings, kJunctionWeld);
  split_four_plane_vertices(outline, regions, planes);
}

// A region that snapping folded over itself (a vertex moved past one of its
// own edges) would come out of make_valid covering its neighbour, which then
// loses its plane to it (a hip roof's face, once its points came in another
// order): such a region keeps its shape from before the snap, and
// remove_overlaps and fix_coverage settle the seams with its neighbours.
void roof::undo_folding_snaps(std::vector<MultiPolygon2>& regions, const std::vector<MultiPolygon2>& before) {
  for (size_t i = 0; i < regions.size(); ++i)
    if (std::abs(area(poly::make_valid(regions[i])) - area(regions[i])) > kFoldAreaChange)
      regions[i] = before[i];
}

// Snapping may make neighbours overlap slightly; an area belongs to one region only.
void roof::remove_overlaps(std::vector<MultiPolygon2>& regions) {
  MultiPolygon2 taken;
  for (auto& r : regions) {
    r = poly::drop_small(poly::subtract(poly::make_valid(r), taken), kOverlapDust);
    taken = poly::unite(taken, r);
  }
}

void split_four_plane_vertices(const Polygon2& outline, std::vector<MultiPolygon2>& regions,
                               const std::vector<Plane>& planes) {
  std::map<Ring2*, std::map<size_t, std::vector<Vec2>>> replace;  // ring -> vertex -> what takes its place
  for (const auto& [key, corners] : corners_by_vertex(regions)) {
    const Vec2 v(key.first, key.second);
    Vec2 ea, eb;
    if (corners.size() != 4 || on_outline(outline, v, ea, eb)) continue;
    const std::vector<Corner> round = round_the_vertex(corners);
    const auto ridge = round.empty() ? std::nullopt : short_ridge(round, planes, v);
    if (!ridge) continue;
    const Corner& end1 = round[(ridge->first + 1) % 4];
    for (size_t k = 0; k < 4; ++k) {
      const Corner& c = round[k];
      if (k == (ridge->first + 1) % 4) replace[c.ring][c.at] = {ridge->end1};
      else if (k == (ridge->first + 3) % 4) replace[c.ring][c.at] = {ridge->end3};
      else if (end1.ends_at(c.prev))  // along the ridge, coming from end 1's side
        replace[c.ring][c.at] = {ridge->end1, ridge->end3};
      else
        replace[c.ring][c.at] = {ridge->end3, ridge->end1};
    }
  }
  for (auto& [ring, at_index] : replace) {
    Ring2 out;
    for (size_t i = 0; i < ring->size(); ++i) {
      auto it = at_index.find(i);
      if (it == at_index.end()) out.push_back((*ring)[i]);
      else out.insert(out.end(), it->second.begin(), it->second.end());
    }
    *ring = std::move(out);
  }
}

void node_rings(std::vector<Ring2*>& rings, double tol) {
  Welder<Vec2> welder(tol);
  for (auto* r : rings)
    for (auto& v : *r) welder.weld(v);
  const EdgeNoder<Vec2> noder(welder.seen(), tol);
  for (auto* r : rings) {
    Ring2 out = noder.insert_on_edges(*r);
    // Drop consecutive duplicates produced by welding.
    Ring2 clean;
    for (const auto& v : out)
      if (clean.empty() || (v - clean.back()).norm() >= tol) clean.push_back(v);
    while (clean.size() > 1 && (clean.front() - clean.back()).norm() < tol) clean.pop_back();
    *r = clean;
  }
}

}  // namespace c3d

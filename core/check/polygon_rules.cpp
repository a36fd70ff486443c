#include "core/check/polygon_rules.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/geometry/geometry.h"
#include "core/check/solid_check.h"

namespace c3d {

int VertexSnap::id(const Vec3& p) {
  std::array<long long, 3> k{std::llround(p.x() / tol_), std::llround(p.y() / tol_),
                             std::llround(p.z() / tol_)};
  auto [it, fresh] = map_.try_emplace(k, int(points.size()));
  if (fresh) points.push_back(p);
  return it->second;
}

namespace {

// Ring rules; returns the ring's snapped ids without consecutive repeats.
std::vector<int> check_ring(const Ring3& r, const Vec3& normal, VertexSnap& snap, const std::string& where,
                            std::vector<PolygonIssue>& issues) {
  std::vector<int> ids;
  bool repeated = false;
  // val3dity merges a vertex into the first one it read within its tolerance
  // (by distance, not by grid cell), so two neighbours 0.9 mm apart across a
  // cell border can repeat there: closer than the tolerance counts as one.
  auto too_close = [&](const Vec3& a, const Vec3& b) { return (a - b).norm() < snap.tol(); };
  for (size_t k = 0; k < r.size(); ++k) {
    int i = snap.id(r[k]);
    if (!ids.empty() && (ids.back() == i || too_close(r[k - 1], r[k]))) {
      repeated = true;
      continue;
    }
    ids.push_back(i);
  }
  if (ids.size() > 1 && (ids.front() == ids.back() || too_close(r.front(), r.back())))
    ids.pop_back(), repeated = true;
  if (repeated) issues.push_back({kConsecutivePointsSame, where, "consecutive duplicate vertices"});
  if (ids.size() < 3) {
    issues.push_back({kTooFewPoints, where, std::to_string(ids.size()) + " distinct vertices"});
    return ids;
  }
  std::vector<int> sorted = ids;
  std::sort(sorted.begin(), sorted.end());
  if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end()) {
    issues.push_back({kRingSelfIntersection, where, "ring passes twice through one vertex"});
    return ids;
  }
  Ring3 clean;
  for (int i : ids) clean.push_back(snap.points[size_t(i)]);
  if (area(clean) < 1e-6) {
    issues.push_back({kRingSelfIntersection, where, "zero-area (collapsed) ring"});
    return ids;
  }
  if (auto cross = ring_crossing(clean, normal))
    issues.push_back({kRingSelfIntersection, where,
                      "edges " + std::to_string(cross->first) + " and " + std::to_string(cross->second) +
                          " intersect"});
  return ids;
}

}  // namespace

Face on_export_grid(Face f) {
  auto round = [](Ring3& ring) {
    for (Vec3& v : ring) v = (v / kExportGridM).array().round() * kExportGridM;
  };
  round(f.ring);
  for (Ring3& h : f.holes) round(h);
  return f;
}

bool check_polygon(const Face& f, const PolygonRules& rules, VertexSnap& snap,
                   std::vector<std::vector<int>>& rings, std::vector<PolygonIssue>& issues) {
  const Vec3 n = unit_normal(f);
  const size_t before = issues.size();
  rings.push_back(check_ring(f.ring, n, snap, "", issues));
  for (size_t k = 0; k < f.holes.size(); ++k)
    rings.push_back(check_ring(f.holes[k], n, snap, " hole " + std::to_string(k), issues));
  if (issues.size() != before) return false;
  const double worst = planarity_deviation(f);
  if (worst > rules.planarity_tol) {
    char msg[64];
    std::snprintf(msg, sizeof msg, "vertex %.1f cm from the fitted plane", worst * 100);
    issues.push_back({kNonPlanarDistancePlane, "", msg});
    return false;
  }
  if (tilted_triangle(f, rules.normals_tol_deg)) {
    issues.push_back({kNonPlanarNormalsDeviation, "", "triangle normal deviates from the polygon's"});
    return false;
  }
  return true;
}

std::vector<Face> snapped_together(std::vector<Face> faces, double tol) {
  using Cell = std::array<long long, 3>;
  std::map<Cell, std::vector<Vec3>> grid;  // cells of side tol: a close pair lies in neighbouring cells
  auto snap = [&](Vec3& p) {
    const Cell c{std::llround(std::floor(p.x() / tol)), std::llround(std::floor(p.y() / tol)),
                 std::llround(std::floor(p.z() / tol))};
    for (long long dx = -1; dx <= 1; ++dx)
      for (long long dy = -1; dy <= 1; ++dy)
        for (long long dz = -1; dz <= 1; ++dz) {
          auto it = grid.find({c[0] + dx, c[1] + dy, c[2] + dz});
          if (it == grid.end()) continue;
          for (const Vec3& q : it->second)
            if ((q - p).norm() < tol) {
              p = q;
              return;
            }
        }
    grid[c].push_back(p);
  };
  for (Face& f : faces) {
    for (Vec3& v : f.ring) snap(v);
    for (Ring3& h : f.holes)
      for (Vec3& v : h) snap(v);
  }
  return faces;
}

}  // namespace c3d

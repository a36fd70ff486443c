// optimize_building: element faces -> constrained mesh -> optimizer -> faces.
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "core/geometry/geometry.h"
#include "core/optimizer/optimizer.h"

namespace c3d {
namespace {

using Key = std::array<long long, 3>;
Key key_of(const Vec3& p) {  // 0.1 mm: faces of one building share exact vertices
  return {std::llround(p.x() * 1e4), std::llround(p.y() * 1e4), std::llround(p.z() * 1e4)};
}

// In-plane 2-D coordinates of a ring.
std::vector<Vec2> project_2d(const Ring3& ring, const Vec3& n) {
  Vec3 u = n.unitOrthogonal(), v = n.cross(u);
  std::vector<Vec2> out;
  for (const Vec3& p : ring) out.emplace_back(p.dot(u), p.dot(v));
  return out;
}

bool inside_2d(const std::vector<Vec2>& poly, const Vec2& p) {
  bool in = false;
  for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++)
    if ((poly[i].y() > p.y()) != (poly[j].y() > p.y()) &&
        p.x() < poly[j].x() + (poly[i].x() - poly[j].x()) * (p.y() - poly[j].y()) / (poly[i].y() - poly[j].y()))
      in = !in;
  return in;
}

// Ear clipping of a simple polygon (holes are not cut out: only the ring
// vertices are refined, so covering them is harmless).
std::vector<std::array<int, 3>> ear_clip(const std::vector<Vec2>& pts) {
  std::vector<int> idx(pts.size());
  for (std::size_t i = 0; i < idx.size(); ++i) idx[i] = static_cast<int>(i);
  if (signed_area(Ring2(pts.begin(), pts.end())) < 0) std::reverse(idx.begin(), idx.end());
  auto cross = [&](int a, int b, int c) {
    return (pts[b] - pts[a]).x() * (pts[c] - pts[a]).y() - (pts[b] - pts[a]).y() * (pts[c] - pts[a]).x();
  };
  std::vector<std::array<int, 3>> tris;
  while (idx.size() > 3) {
    bool clipped = false;
    for (std::size_t i = 0; i < idx.size() && !clipped; ++i) {
      int a = idx[(i + idx.size() - 1) % idx.size()], b = idx[i], c = idx[(i + 1) % idx.size()];
      if (cross(a, b, c) <= 0) continue;
      bool empty = true;
      for (int p : idx)
        if (p != a && p != b && p != c && cross(a, b, p) >= 0 && cross(b, c, p) >= 0 && cross(c, a, p) >= 0)
          empty = false;
      if (!empty) continue;
      tris.push_back({a, b, c});
      idx.erase(idx.begin() + static_cast<long>(i));
      clipped = true;
    }
    if (!clipped) break;  // degenerate ring: fan the rest
  }
  for (std::size_t i = 1; i + 1 < idx.size(); ++i) tris.push_back({idx[0], idx[i], idx[i + 1]});
  return tris;
}

// PrimitivePlane of a face: Newell normal through the centroid, refitted (PCA) to the
// points near it whose projection falls inside the face.
PrimitivePlane face_plane(const Face& f, const std::vector<Vec3>& points) {
  PrimitivePlane pl;
  pl.n = newell_normal(f.ring).normalized();
  Vec3 c = Vec3::Zero();
  for (const Vec3& p : f.ring) c += p;
  c /= static_cast<double>(f.ring.size());
  pl.d = -pl.n.dot(c);
  if (points.empty()) return pl;
  std::vector<Vec2> poly = project_2d(f.ring, pl.n);
  Vec3 u = pl.n.unitOrthogonal(), v = pl.n.cross(u);
  std::vector<Vec3> near;
  for (const Vec3& p : points)
    if (std::fabs(pl.distance(p)) < 0.25 && inside_2d(poly, Vec2(p.dot(u), p.dot(v)))) near.push_back(p);
  if (near.size() < 10) return pl;
  Vec3 m = Vec3::Zero();
  for (const Vec3& p : near) m += p;
  m /= static_cast<double>(near.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const Vec3& p : near) cov += (p - m) * (p - m).transpose();
  Vec3 n = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(cov).eigenvectors().col(0);
  if (n.dot(pl.n) < 0) n = -n;
  if (n.dot(pl.n) < std::cos(15 * 3.14159265358979 / 180)) return pl;
  return PrimitivePlane{n, -n.dot(m)};
}

// Vertices on three or more planes go to their least-squares common point.
void snap_corners(ConstrainedMesh& cm) {
  std::vector<std::set<int>> planes(cm.mesh.vertices.size());
  for (std::size_t t = 0; t < cm.mesh.triangles.size(); ++t)
    for (int v : cm.mesh.triangles[t]) planes[v].insert(cm.tri_plane[t]);
  for (std::size_t v = 0; v < planes.size(); ++v) {
    if (planes[v].size() < 3) continue;
    Eigen::Matrix3d A = 1e-6 * Eigen::Matrix3d::Identity();
    Vec3 b = 1e-6 * cm.mesh.vertices[v];
    for (int k : planes[v]) {
      const PrimitivePlane& p = cm.planes[k];
      A += p.n * p.n.transpose();
      b += -p.d * p.n;
    }
    cm.mesh.vertices[v] = A.ldlt().solve(b);
  }
}

}  // namespace

OptimizeReport optimize_building(Building& building, const std::vector<Vec3>& points,
                                 const OptimizerOptions& options) {
  ConstrainedMesh cm;
  std::map<Key, int> index;
  auto vertex = [&](const Vec3& p) {
    auto [it, added] = index.emplace(key_of(p), static_cast<int>(cm.mesh.vertices.size()));
    if (added) cm.mesh.vertices.push_back(p);
    return it->second;
  };
  static const std::vector<Vec3> kNoPoints;
  for (const Element& e : building.elements) {
    // One constraint plane per roof element (its pieces inside and beyond the
    // walls stay coplanar), refitted to the roof points; walls, ground and
    // soffits keep their planes, as the roof points say nothing about them.
    const bool roof = e.type == ElementType::Roof;
    int shared_plane = -1;
    if (roof && !e.faces.empty()) {
      const Face* largest = &e.faces.front();
      for (const Face& f : e.faces)
        if (area(f) > area(*largest)) largest = &f;
      shared_plane = static_cast<int>(cm.planes.size());
      cm.planes.push_back(face_plane(*largest, points));
    }
    for (const Face& f : e.faces) {
      if (f.ring.size() < 3) continue;
      int plane = shared_plane;
      if (plane < 0) {
        plane = static_cast<int>(cm.planes.size());
        cm.planes.push_back(face_plane(f, kNoPoints));
      }
      std::vector<int> ids;
      for (const Vec3& p : f.ring) ids.push_back(vertex(p));
      for (auto t : ear_clip(project_2d(f.ring, cm.planes[plane].n))) {
        cm.mesh.triangles.push_back({ids[t[0]], ids[t[1]], ids[t[2]]});
        cm.tri_plane.push_back(plane);
      }
    }
  }
  cm.lines = adjacent_plane_lines(cm);
  OptimizerOptions o = options;
  o.split_junctions = false;  // face edges already follow the junctions
  o.subdivide = false;
  OptimizeReport r = optimize_mesh(cm, o);
  snap_corners(cm);
  std::map<Key, Vec3> moved;
  for (const auto& [k, i] : index) moved[k] = cm.mesh.vertices[i];
  auto update = [&](Ring3& ring) {
    for (Vec3& p : ring)
      if (auto it = moved.find(key_of(p)); it != moved.end()) p = it->second;
  };
  for (Element& e : building.elements) {
    double a = 0, pa = 0;
    for (Face& f : e.faces) {
      update(f.ring);
      for (Ring3& h : f.holes) update(h);
      a += area(f);
      pa += plan_area(f);
    }
    e.area = e.type == ElementType::OuterCeiling ? pa : a;  // outer ceiling: plan area
    e.plan_area = pa;
  }
  for (Face& f : building.solid) {
    update(f.ring);
    for (Ring3& h : f.holes) update(h);
  }
  return r;
}

}  // namespace c3d

#include "core/mesh/regions.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>

#include "core/mesh/spacing.h"


namespace c3d {

namespace {

using Edge = std::pair<int, int>;

Edge edge_of(int a, int b) { return a < b ? Edge{a, b} : Edge{b, a}; }

// Each face's neighbours across its edges (a non-manifold edge joins all its faces).
std::vector<std::vector<int>> face_neighbours(const TriMesh& m) {
  std::map<Edge, std::vector<int>> faces_of;
  for (size_t f = 0; f < m.triangles.size(); ++f)
    for (int k = 0; k < 3; ++k) faces_of[edge_of(m.triangles[f][k], m.triangles[f][(k + 1) % 3])].push_back(int(f));
  std::vector<std::vector<int>> out(m.triangles.size());
  for (const auto& [edge, faces] : faces_of)
    for (int f : faces)
      for (int g : faces)
        if (f != g) out[size_t(f)].push_back(g);
  return out;
}

std::vector<Vec3> face_normals(const TriMesh& m) {
  std::vector<Vec3> out;
  for (const auto& t : m.soup()) {
    const Vec3 n = (t[1] - t[0]).cross(t[2] - t[0]);
    out.push_back(n.norm() > 0 ? Vec3(n.normalized()) : Vec3::Zero());
  }
  return out;
}

double angle_deg(const Vec3& a, const Vec3& b) {
  return std::acos(std::clamp(a.dot(b), -1.0, 1.0)) * 180 / M_PI;
}

std::vector<int> vertices_of(const TriMesh& m, const std::vector<int>& faces) {
  std::vector<int> vertices;
  for (int f : faces) vertices.insert(vertices.end(), m.triangles[size_t(f)].begin(), m.triangles[size_t(f)].end());
  std::sort(vertices.begin(), vertices.end());
  vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
  return vertices;
}

// RMS distance of the region's vertices to their best plane.
double plane_rms(const TriMesh& m, const std::vector<int>& faces) {
  return std::sqrt(principal_axes(m.vertices, vertices_of(m, faces)).variance[2]);
}

std::vector<std::vector<int>> faces_by_region(const std::vector<int>& face_region, size_t regions) {
  std::vector<std::vector<int>> out(regions);
  for (size_t f = 0; f < face_region.size(); ++f)
    if (face_region[f] >= 0 && size_t(face_region[f]) < regions) out[size_t(face_region[f])].push_back(int(f));
  return out;
}

Vec3 centre_of(const TriMesh& m, int f) {
  const auto& t = m.triangles[size_t(f)];
  return (m.vertices[size_t(t[0])] + m.vertices[size_t(t[1])] + m.vertices[size_t(t[2])]) / 3;
}

// Whether the face's corners lie within `within` of the plane through
// `centre` across `normal`.
bool near_plane(const TriMesh& m, int f, const Vec3& centre, const Vec3& normal, double within) {
  for (int v : m.triangles[size_t(f)])
    if (std::abs(normal.dot(m.vertices[size_t(v)] - centre)) > within) return false;
  return true;
}

// Faces grown from the smoothest unassigned one, breadth first.
std::vector<std::vector<int>> grown(const TriMesh& m, const RegionParams& p,
                                    const std::vector<std::vector<int>>& next, const std::vector<Vec3>& n) {
  const size_t faces = m.triangles.size();
  std::vector<double> sharpest(faces, 0.0);
  for (size_t f = 0; f < faces; ++f)
    for (int g : next[f]) sharpest[f] = std::max(sharpest[f], angle_deg(n[f], n[size_t(g)]));
  std::vector<int> order(faces);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return sharpest[size_t(a)] < sharpest[size_t(b)]; });
  std::vector<int> region(faces, -1);
  std::vector<char> on_plane(faces, 0);  // joined as lying on its region's plane
  std::vector<std::vector<int>> out;
  for (int seed : order) {
    if (region[size_t(seed)] >= 0) continue;
    std::vector<int> members{seed};
    region[size_t(seed)] = int(out.size());
    Vec3 sum = n[size_t(seed)];  // the region's mean normal, unnormalised
    Vec3 centre_sum = centre_of(m, seed);  // and its faces' centres, summed
    for (size_t k = 0; k < members.size(); ++k) {
      const int f = members[k];
      // A face on a ridge joins but does not carry the region over it, unless
      // it lies on the region's plane (a noisy plane's faces turn sharply).
      if (k > 0 && !on_plane[size_t(f)] && sharpest[size_t(f)] > p.curvature_deg) continue;
      for (int g : next[size_t(f)]) {
        if (region[size_t(g)] >= 0) continue;
        // Smooth to its neighbour (a curved surface turns slowly), or to the
        // region as a whole (a noisy plane's faces tilt both ways), or on
        // the region's plane (a noisy plane's small faces tilt steeply).
        const Vec3& ng = n[size_t(g)];
        const Vec3 mean = sum.normalized();
        const bool planar = angle_deg(mean, ng) <= p.smooth_deg ||
                            (angle_deg(mean, ng) <= p.on_plane_deg &&
                             near_plane(m, g, centre_sum / double(members.size()), mean, p.flat_m));
        if (!planar && angle_deg(n[size_t(f)], ng) > p.smooth_deg) continue;
        on_plane[size_t(g)] = planar;
        region[size_t(g)] = int(out.size());
        members.push_back(g);
        sum += ng;
        centre_sum += centre_of(m, g);
      }
    }
    out.push_back(std::move(members));
  }
  return out;
}

}  // namespace

const char* region_kind_name(RegionKind k) {
  switch (k) {
    case RegionKind::Planar: return "planar";
    case RegionKind::Curved: return "curved";
    case RegionKind::Detail: return "detail";
  }
  return "?";
}

size_t MeshRegions::count(RegionKind k) const { return size_t(std::count(kinds.begin(), kinds.end(), k)); }

MeshRegions segment_regions(const TriMesh& mesh, const RegionParams& p) {
  MeshRegions r;
  r.face_region.assign(mesh.triangles.size(), -1);
  if (mesh.triangles.empty()) return r;
  const auto next = face_neighbours(mesh);
  const auto normals = face_normals(mesh);
  const auto regions = grown(mesh, p, next, normals);
  // Small regions are detail; touching ones become one detail region.
  std::vector<int> id(regions.size(), -1);
  for (size_t k = 0; k < regions.size(); ++k) {
    if (regions[k].size() < p.min_faces) continue;
    id[k] = int(r.kinds.size());
    r.kinds.push_back(plane_rms(mesh, regions[k]) <= p.flat_m ? RegionKind::Planar : RegionKind::Curved);
  }
  for (size_t k = 0; k < regions.size(); ++k)
    for (int f : regions[k]) r.face_region[size_t(f)] = id[k];
  for (size_t k = 0; k < regions.size(); ++k) {
    if (id[k] >= 0) continue;
    // A small region enclosed by one large one (two thirds of the faces
    // across its border: noise on a plane) joins it; one among several
    // (a frame's corner, a sill) joins a touching detail region, else
    // starts one.
    std::map<int, int> across;  // region -> faces across the border
    int joined = -1, outside = 0;
    for (int f : regions[k])
      for (int g : next[size_t(f)]) {
        const int other = r.face_region[size_t(g)];
        if (std::find(regions[k].begin(), regions[k].end(), g) != regions[k].end()) continue;
        ++outside;
        if (other >= 0) ++across[other];
        if (other >= 0 && r.kinds[size_t(other)] == RegionKind::Detail) joined = other;
      }
    for (const auto& [other, n] : across)
      if (r.kinds[size_t(other)] != RegionKind::Detail && 3 * n >= 2 * outside) joined = other;
    if (joined < 0) joined = int(r.kinds.size()), r.kinds.push_back(RegionKind::Detail);
    for (int f : regions[k]) r.face_region[size_t(f)] = joined;
  }
  return r;
}

std::vector<RegionFrame> planar_frames(const TriMesh& mesh, const MeshRegions& regions) {
  const auto faces = faces_by_region(regions.face_region, regions.kinds.size());
  std::vector<RegionFrame> out;
  for (size_t r = 0; r < faces.size(); ++r) {
    if (regions.kinds[r] != RegionKind::Planar || faces[r].empty()) continue;
    const PrincipalAxes p = principal_axes(mesh.vertices, vertices_of(mesh, faces[r]));
    out.push_back({int(r), p.centre, p.axes});
  }
  return out;
}

std::vector<RegionShape> region_shapes(const TriMesh& mesh, const std::vector<int>& face_region,
                                       const std::vector<RegionFrame>& frames) {
  size_t regions = 0;
  for (const RegionFrame& f : frames) regions = std::max(regions, size_t(f.region + 1));
  const auto faces = faces_by_region(face_region, regions);
  std::vector<RegionShape> out;
  for (const RegionFrame& frame : frames) {
    RegionShape s{frame.region, faces[size_t(frame.region)].size()};
    if (s.faces > 0) {
      Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
      for (int v : vertices_of(mesh, faces[size_t(frame.region)])) {
        const Vec3 d = mesh.vertices[size_t(v)] - frame.centre;
        const Vec3 along(d.dot(frame.axes[0]), d.dot(frame.axes[1]), d.dot(frame.axes[2]));
        lo = lo.cwiseMin(along), hi = hi.cwiseMax(along);
      }
      s.length = hi.x() - lo.x(), s.width = hi.y() - lo.y(), s.thickness = hi.z() - lo.z();
    }
    out.push_back(s);
  }
  return out;
}

std::vector<Vec3> border_vertices(const TriMesh& mesh, const std::vector<int>& face_region) {
  std::vector<int> first(mesh.vertices.size(), -1);
  std::vector<bool> border(mesh.vertices.size(), false);
  for (size_t f = 0; f < mesh.triangles.size() && f < face_region.size(); ++f)
    for (int v : mesh.triangles[f]) {
      int& seen = first[size_t(v)];
      if (seen < 0) seen = face_region[f];
      else if (seen != face_region[f]) border[size_t(v)] = true;
    }
  std::vector<Vec3> out;
  for (size_t v = 0; v < border.size(); ++v)
    if (border[v]) out.push_back(mesh.vertices[v]);
  return out;
}

PlanarChange planar_change(const std::vector<RegionShape>& dense, const std::vector<RegionShape>& light) {
  PlanarChange c;
  for (size_t k = 0; k < dense.size() && k < light.size(); ++k) {
    if (dense[k].faces == 0) continue;
    ++c.regions;
    if (light[k].faces == 0) {
      ++c.lost;
      continue;
    }
    c.extent_change = std::max({c.extent_change, std::abs(light[k].length - dense[k].length),
                                std::abs(light[k].width - dense[k].width)});
    c.thickness = std::max(c.thickness, light[k].thickness);
  }
  return c;
}

}  // namespace c3d

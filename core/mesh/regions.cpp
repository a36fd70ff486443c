#include "core/mesh/regions.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>

#include <Eigen/Eigenvalues>

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

// RMS distance of the region's vertices to their best plane.
double plane_rms(const TriMesh& m, const std::vector<int>& faces) {
  std::vector<int> vertices;
  for (int f : faces) vertices.insert(vertices.end(), m.triangles[size_t(f)].begin(), m.triangles[size_t(f)].end());
  std::sort(vertices.begin(), vertices.end());
  vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
  Vec3 mean = Vec3::Zero();
  for (int v : vertices) mean += m.vertices[size_t(v)];
  mean /= double(vertices.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (int v : vertices) {
    const Vec3 d = m.vertices[size_t(v)] - mean;
    cov += d * d.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov / double(vertices.size()));
  return std::sqrt(std::max(0.0, eig.eigenvalues()(0)));
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
  std::vector<std::vector<int>> out;
  for (int seed : order) {
    if (region[size_t(seed)] >= 0) continue;
    std::vector<int> members{seed};
    region[size_t(seed)] = int(out.size());
    Vec3 sum = n[size_t(seed)];  // the region's mean normal, unnormalised
    for (size_t k = 0; k < members.size(); ++k) {
      const int f = members[k];
      if (sharpest[size_t(f)] > p.curvature_deg && k > 0) continue;  // joins, does not carry on
      for (int g : next[size_t(f)]) {
        if (region[size_t(g)] >= 0) continue;
        // Smooth to its neighbour (a curved surface turns slowly), or to the
        // region as a whole (a noisy plane's faces tilt both ways).
        const Vec3& ng = n[size_t(g)];
        if (angle_deg(n[size_t(f)], ng) > p.smooth_deg && angle_deg(sum.normalized(), ng) > p.smooth_deg) continue;
        region[size_t(g)] = int(out.size());
        members.push_back(g);
        sum += ng;
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
    // A small region joins a touching detail region, else starts one.
    int joined = -1;
    for (int f : regions[k])
      for (int g : next[size_t(f)]) {
        const int other = r.face_region[size_t(g)];
        if (other >= 0 && r.kinds[size_t(other)] == RegionKind::Detail) joined = other;
      }
    if (joined < 0) joined = int(r.kinds.size()), r.kinds.push_back(RegionKind::Detail);
    for (int f : regions[k]) r.face_region[size_t(f)] = joined;
  }
  return r;
}

std::vector<std::array<int, 2>> region_borders(const TriMesh& mesh, const MeshRegions& regions) {
  std::map<Edge, std::vector<int>> regions_of;
  for (size_t f = 0; f < mesh.triangles.size(); ++f)
    for (int k = 0; k < 3; ++k)
      regions_of[edge_of(mesh.triangles[f][k], mesh.triangles[f][(k + 1) % 3])].push_back(regions.face_region[f]);
  std::vector<std::array<int, 2>> out;
  for (const auto& [edge, ids] : regions_of)
    if (std::adjacent_find(ids.begin(), ids.end(), std::not_equal_to<int>()) != ids.end())
      out.push_back({edge.first, edge.second});
  return out;
}

}  // namespace c3d

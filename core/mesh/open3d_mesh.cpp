// Ball pivoting and screened Poisson through Open3D 0.16, which has what CGAL
// 5.5 lacks (CGAL's Poisson is not the screened one; it has no ball
// pivoting). Open3D's headers stay in this translation unit.
#include "core/mesh/open3d_mesh.h"

#include <open3d/geometry/PointCloud.h>
#include <open3d/geometry/TriangleMesh.h>

#include <algorithm>
#include <cmath>

namespace c3d {

namespace {

open3d::geometry::PointCloud open3d_cloud(const std::vector<Vec3>& points, const std::vector<Vec3>& normals) {
  open3d::geometry::PointCloud pc;
  pc.points_.assign(points.begin(), points.end());
  pc.normals_.assign(normals.begin(), normals.end());
  return pc;
}

TriMesh from_open3d(const open3d::geometry::TriangleMesh& m) {
  TriMesh out;
  out.vertices.assign(m.vertices_.begin(), m.vertices_.end());
  for (const Eigen::Vector3i& t : m.triangles_) out.triangles.push_back({t.x(), t.y(), t.z()});
  return out;
}

}  // namespace

std::vector<double> pivoting_radii(const PointSpacing& s) {
  std::vector<double> radii = {s.mean, s.p95, 3 * s.mean};
  std::sort(radii.begin(), radii.end());
  radii.erase(std::unique(radii.begin(), radii.end()), radii.end());
  return radii;
}

int poisson_depth(const std::vector<Vec3>& points, const PointSpacing& s) {
  Vec3 lo = points.front(), hi = points.front();
  for (const Vec3& p : points) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  const double cube = 1.1 * (hi - lo).maxCoeff();  // Open3D's scale: the cube 1.1 times the points' extent
  const int depth = int(std::ceil(std::log2(cube / std::max(s.mean, 1e-6))));
  return std::clamp(depth, kMinPoissonDepth, kMaxPoissonDepth);
}

TriMesh ball_pivoting(const std::vector<Vec3>& points, const std::vector<Vec3>& normals, const PointSpacing& s) {
  const auto mesh = open3d::geometry::TriangleMesh::CreateFromPointCloudBallPivoting(open3d_cloud(points, normals),
                                                                                     pivoting_radii(s));
  return mesh ? from_open3d(*mesh) : TriMesh{};
}

TriMesh screened_poisson(const std::vector<Vec3>& points, const std::vector<Vec3>& normals, const PointSpacing& s) {
  const auto [mesh, density] = open3d::geometry::TriangleMesh::CreateFromPointCloudPoisson(
      open3d_cloud(points, normals), size_t(poisson_depth(points, s)), 0.0f, 1.1f, false, 1);
  return mesh ? from_open3d(*mesh) : TriMesh{};
}

TriMesh alpha_shape(const std::vector<Vec3>& points, const PointSpacing& s) {
  const auto mesh = open3d::geometry::TriangleMesh::CreateFromPointCloudAlphaShape(open3d_cloud(points, {}), s.p95);
  return mesh ? from_open3d(*mesh) : TriMesh{};
}

TriMesh vertex_clustering(const TriMesh& mesh, double cell) {
  open3d::geometry::TriangleMesh m;
  m.vertices_.assign(mesh.vertices.begin(), mesh.vertices.end());
  for (const auto& t : mesh.triangles) m.triangles_.emplace_back(t[0], t[1], t[2]);
  return from_open3d(*m.SimplifyVertexClustering(cell));
}

}  // namespace c3d

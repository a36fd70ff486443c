#include "core/mesh/mesh_metrics.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "core/evaluate/evaluate.h"
#include "core/mesh/point_index.h"

namespace c3d {

namespace {

// Edge uses: closed when every edge has two faces, manifold when none has more.
void edge_counts(const TriMesh& mesh, MeshMetrics& m) {
  std::map<std::pair<int, int>, int> uses;
  for (const auto& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) {
      const int a = t[size_t(k)], b = t[size_t((k + 1) % 3)];
      ++uses[{std::min(a, b), std::max(a, b)}];
    }
  m.closed = !uses.empty(), m.manifold = true;
  for (const auto& [edge, n] : uses) {
    m.closed &= n == 2;
    m.manifold &= n <= 2;
  }
}

// The farthest of the mesh's vertices and face centres from any point.
double farthest_from_points(const TriMesh& mesh, const std::vector<Vec3>& points) {
  if (points.empty() || mesh.triangles.empty()) return 0;
  const PointIndex index(points);
  double farthest = 0;
  const auto visit = [&](const Vec3& p) { farthest = std::max(farthest, index.nearest(p)); };
  for (const Vec3& v : mesh.vertices) visit(v);
  for (const auto& t : mesh.soup()) visit((t[0] + t[1] + t[2]) / 3);
  return farthest;
}

// The divergence theorem over the triangles: the volume a closed mesh encloses.
double enclosed_volume(const TriMesh& mesh) {
  double six = 0;
  for (const auto& t : mesh.soup()) six += t[0].dot(t[1].cross(t[2]));
  return std::abs(six) / 6;
}

}  // namespace

std::vector<double> distances_to(const TriMesh& mesh, const std::vector<Vec3>& points) {
  if (mesh.triangles.empty()) return std::vector<double>(points.size(), INFINITY);
  std::vector<Face> faces;  // the evaluation's nearest-surface index, as for a model's faces
  faces.reserve(mesh.triangles.size());
  for (const auto& t : mesh.soup()) faces.push_back(Face{{t[0], t[1], t[2]}, {}});
  std::vector<double> d;
  d.reserve(points.size());
  for (const SurfaceHit& hit : FaceIndex(faces).nearest(points))
    d.push_back(std::isnan(hit.distance) ? INFINITY : hit.distance);  // NaN: every triangle degenerate
  return d;
}

Spread spread_of(std::vector<double> d) {
  Spread s;
  if (d.empty()) return s;
  double sum = 0, sum2 = 0;
  for (double x : d) sum += x, sum2 += x * x;
  const double n = double(d.size());
  s.mean = sum / n;
  s.std = std::sqrt(std::max(0.0, sum2 / n - s.mean * s.mean));
  std::sort(d.begin(), d.end());
  s.p95 = d[size_t(0.95 * (n - 1) + 0.5)];
  s.max = d.back();
  return s;
}

MeshMetrics measure_mesh(const TriMesh& mesh, const std::vector<Vec3>& points, const PointSpacing& spacing) {
  MeshMetrics m;
  m.faces = mesh.triangles.size(), m.vertices = mesh.vertices.size();
  edge_counts(mesh, m);
  if (m.closed) m.volume = enclosed_volume(mesh);
  if (mesh.triangles.empty() || points.empty()) return m;
  const std::vector<double> d = distances_to(mesh, points);
  const double reach = 2 * spacing.mean;
  m.far_share = double(std::count_if(d.begin(), d.end(), [&](double x) { return x > reach; })) / double(d.size());
  const Spread s = spread_of(d);
  m.mean = s.mean, m.std = s.std, m.p95 = s.p95, m.max = s.max;
  m.mesh_to_cloud = farthest_from_points(mesh, points);
  return m;
}

double upward_area(const TriMesh& mesh, double min_normal_z) {
  double sum = 0;
  for (const auto& t : mesh.soup()) {
    const Vec3 n = (t[1] - t[0]).cross(t[2] - t[0]);  // twice the area, along the normal
    const double doubled = n.norm();
    if (doubled > 0 && n.z() >= min_normal_z * doubled) sum += doubled / 2;
  }
  return sum;
}

}  // namespace c3d

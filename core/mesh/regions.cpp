#include "core/mesh/regions.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>

#include "core/mesh/spacing.h"

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

std::vector<int> vertices_of(const TriMesh& m, const std::vector<int>& faces) {
  std::vector<int> vertices;
  for (int f : faces) vertices.insert(vertices.end(), m.triangles[size_t(f)].begin(), m.triangles[size_t(f)].end());
  std::sort(vertices.begin(), vertices.end());
  vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
  return vertices;
}

// RMS distance of the faces' vertices to the plane through `plane`'s centre
// across its third axis.
double rms_off_plane(const TriMesh& m, const std::vector<int>& faces, const PrincipalAxes& plane) {
  const std::vector<int> vertices = vertices_of(m, faces);
  double sum = 0;
  for (int v : vertices) sum += std::pow(plane.axes[2].dot(m.vertices[size_t(v)] - plane.centre), 2);
  return std::sqrt(sum / double(std::max<size_t>(1, vertices.size())));
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

// A growing region's plane: least squares through its faces' centres (a mean
// of noisy faces' normals tilts by degrees, which sets a far face metres off
// a large roof's plane), facing as its faces do on average. Refitted as the
// region grows by a tenth; until it spans a plane, its faces' mean normal.
class GrowingPlane {
 public:
  void add(const Vec3& centre, const Vec3& normal) {
    ++n_, sum_ += centre, outer_ += centre * centre.transpose(), normals_ += normal;
    if (n_ >= next_fit_) refit();
  }
  const Vec3& centre() const { return centre_; }
  const Vec3& normal() const { return normal_; }

 private:
  void refit() {
    next_fit_ = n_ + std::max<size_t>(1, n_ / 10);
    centre_ = sum_ / double(n_);
    normal_ = normals_.normalized();
    if (n_ < 3) return;
    const Eigen::Matrix3d cov = outer_ / double(n_) - centre_ * centre_.transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
    if (eig.eigenvalues()(1) <= 4 * std::max(0.0, eig.eigenvalues()(0))) return;  // a strip, not yet a plane
    const Vec3 n = eig.eigenvectors().col(0);
    normal_ = n.dot(normals_) < 0 ? Vec3(-n) : n;
  }
  size_t n_ = 0, next_fit_ = 1;
  Vec3 sum_ = Vec3::Zero(), normals_ = Vec3::Zero(), centre_ = Vec3::Zero(), normal_ = Vec3::UnitZ();
  Eigen::Matrix3d outer_ = Eigen::Matrix3d::Zero();
};

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
    GrowingPlane plane;
    plane.add(centre_of(m, seed), n[size_t(seed)]);
    for (size_t k = 0; k < members.size(); ++k) {
      const int f = members[k];
      // A face on a ridge joins but does not carry the region over it, unless
      // it lies on the region's plane (a noisy plane's faces turn sharply).
      if (k > 0 && !on_plane[size_t(f)] && sharpest[size_t(f)] > p.curvature_deg) continue;
      for (int g : next[size_t(f)]) {
        if (region[size_t(g)] >= 0) continue;
        // Smooth to its neighbour (a curved surface turns slowly), or to the
        // region's plane (a noisy plane's faces tilt both ways), or on it
        // (a noisy plane's small faces tilt steeply).
        const Vec3& ng = n[size_t(g)];
        const double tilt = angle_deg(plane.normal(), ng);
        const bool planar = tilt <= p.smooth_deg ||
                            (tilt <= p.on_plane_deg && near_plane(m, g, plane.centre(), plane.normal(), p.flat_m));
        if (!planar && angle_deg(n[size_t(f)], ng) > p.smooth_deg) continue;
        on_plane[size_t(g)] = planar;
        region[size_t(g)] = int(out.size());
        members.push_back(g);
        plane.add(centre_of(m, g), ng);
      }
    }
    out.push_back(std::move(members));
  }
  return out;
}

// The connected sets of faces of no region (-1), across their edges.
std::vector<std::vector<int>> unassigned_clusters(const std::vector<int>& face_region,
                                                  const std::vector<std::vector<int>>& next) {
  std::vector<char> seen(face_region.size(), 0);
  std::vector<std::vector<int>> out;
  for (size_t start = 0; start < face_region.size(); ++start) {
    if (face_region[start] >= 0 || seen[start]) continue;
    std::vector<int> cluster{int(start)};
    seen[start] = 1;
    for (size_t k = 0; k < cluster.size(); ++k)
      for (int g : next[size_t(cluster[k])])
        if (face_region[size_t(g)] < 0 && !seen[size_t(g)]) seen[size_t(g)] = 1, cluster.push_back(g);
    out.push_back(std::move(cluster));
  }
  return out;
}

// The large region holding two thirds of the faces across the border of a
// cluster of faces of no region (any such face across is the cluster's own), or -1.
int enclosing_region(const std::vector<int>& faces, const std::vector<int>& face_region,
                     const std::vector<RegionKind>& kinds, const std::vector<std::vector<int>>& next) {
  std::map<int, int> across;  // region -> faces across the border
  int outside = 0;
  for (int f : faces)
    for (int g : next[size_t(f)]) {
      const int other = face_region[size_t(g)];
      if (other < 0) continue;
      ++outside;
      ++across[other];
    }
  for (const auto& [other, n] : across)
    if (kinds[size_t(other)] != RegionKind::Detail && 3 * n >= 2 * outside) return other;
  return -1;
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
  // Regions of `min_faces` or more are planar or curved.
  std::vector<int> id(regions.size(), -1);
  std::vector<PrincipalAxes> planes;  // per region kept
  for (size_t k = 0; k < regions.size(); ++k) {
    if (regions[k].size() < p.min_faces) continue;
    id[k] = int(r.kinds.size());
    planes.push_back(principal_axes(mesh.vertices, vertices_of(mesh, regions[k])));
    r.kinds.push_back(std::sqrt(planes.back().variance[2]) <= p.flat_m ? RegionKind::Planar : RegionKind::Curved);
  }
  for (size_t k = 0; k < regions.size(); ++k)
    for (int f : regions[k]) r.face_region[size_t(f)] = id[k];
  // Touching small regions form one cluster. A cluster whose surroundings
  // are two thirds one large region joins it, if on a planar one it lies on
  // its plane (a speck of noise, not a chimney); the others (a frame's
  // corner, a sill) are detail regions.
  for (const std::vector<int>& cluster : unassigned_clusters(r.face_region, next)) {
    int into = enclosing_region(cluster, r.face_region, r.kinds, next);
    if (into >= 0 && r.kinds[size_t(into)] == RegionKind::Planar &&
        rms_off_plane(mesh, cluster, planes[size_t(into)]) > p.flat_m)
      into = -1;
    if (into < 0) into = int(r.kinds.size()), r.kinds.push_back(RegionKind::Detail);
    for (int f : cluster) r.face_region[size_t(f)] = into;
  }
  r.extremes = planar_extremes(mesh, r);
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

std::vector<Vec3> planar_extremes(const TriMesh& mesh, const MeshRegions& regions) {
  const auto faces = faces_by_region(regions.face_region, regions.kinds.size());
  std::vector<Vec3> out;
  for (const RegionFrame& frame : planar_frames(mesh, regions)) {
    const std::vector<int> vertices = vertices_of(mesh, faces[size_t(frame.region)]);
    for (size_t k = 0; k < 2; ++k) {
      const auto along = [&](int v) { return frame.axes[k].dot(mesh.vertices[size_t(v)]); };
      const auto [lo, hi] = std::minmax_element(vertices.begin(), vertices.end(),
                                                [&](int a, int b) { return along(a) < along(b); });
      out.push_back(mesh.vertices[size_t(*lo)]);
      out.push_back(mesh.vertices[size_t(*hi)]);
    }
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

// Snapping a mesh onto curved primitives (spheres, cylinders, cones): the
// curved half of seed 000's surface optimization.
#include <algorithm>
#include <cmath>

#include "core/optimizer/optimizer.h"
#include "core/optimizer/optimizer_kernels.h"

namespace c3d {

namespace {

constexpr double kPi = 3.14159265358979323846;

// The unit direction from the axis to p, across it (any where p is on it).
Vec3 across_axis(const Vec3& q, const Vec3& axis) {
  const Vec3 radial = q - axis * q.dot(axis);
  return radial.norm() > 0 ? Vec3(radial.normalized()) : Vec3(axis.unitOrthogonal());
}

// 12 floats per surface about `centre`, as the kernel reads them.
std::vector<float> kernel_surfaces(const std::vector<CurvedPrimitive>& surfaces, const Vec3& centre) {
  std::vector<float> out;
  for (const CurvedPrimitive& s : surfaces) {
    const Vec3 c = s.point - centre;
    const double kind = s.kind == CurvedPrimitive::Kind::Sphere ? 0 : s.kind == CurvedPrimitive::Kind::Cylinder ? 1 : 2;
    for (double x : {c.x(), c.y(), c.z(), kind, s.axis.x(), s.axis.y(), s.axis.z(), s.radius, std::cos(s.angle),
                     std::sin(s.angle), 0.0, 0.0})
      out.push_back(static_cast<float>(x));
  }
  return out;
}

// Per vertex: the surface it is snapped onto (-1 none), from the triangles on
// each surface; counts those triangles.
std::vector<std::int32_t> vertex_surfaces(const TriMesh& mesh, const std::vector<CurvedPrimitive>& surfaces,
                                          const CurvedSnapOptions& o, int* on_surfaces) {
  const double min_cos = std::cos(o.assign_angle_deg * kPi / 180);
  std::vector<std::int32_t> vs(mesh.vertices.size(), -1);
  *on_surfaces = 0;
  for (const auto& t : mesh.triangles) {
    const Vec3 &a = mesh.vertices[size_t(t[0])], &b = mesh.vertices[size_t(t[1])], &c = mesh.vertices[size_t(t[2])];
    const Vec3 centroid = (a + b + c) / 3, n = (b - a).cross(c - a);
    if (n.norm() <= 0) continue;
    int best = -1;
    double nearest = o.assign_distance_m;
    for (size_t k = 0; k < surfaces.size(); ++k) {
      const double d = surfaces[k].distance(centroid);
      if (d <= nearest && std::abs(n.normalized().dot(surfaces[k].normal(centroid))) >= min_cos)
        nearest = d, best = int(k);
    }
    if (best < 0) continue;
    ++*on_surfaces;
    for (int v : t) {
      std::int32_t& mine = vs[size_t(v)];
      const Vec3& p = mesh.vertices[size_t(v)];
      if (mine < 0 || surfaces[size_t(best)].distance(p) < surfaces[size_t(mine)].distance(p)) mine = best;
    }
  }
  return vs;
}

double mean_distance(const TriMesh& mesh, const std::vector<CurvedPrimitive>& surfaces,
                     const std::vector<std::int32_t>& vs) {
  double sum = 0;
  size_t n = 0;
  for (size_t i = 0; i < vs.size(); ++i)
    if (vs[i] >= 0) sum += surfaces[size_t(vs[i])].distance(mesh.vertices[i]), ++n;
  return n ? sum / double(n) : 0;
}

}  // namespace

Vec3 CurvedPrimitive::project(const Vec3& p) const {
  const Vec3 q = p - point;
  if (kind == Kind::Sphere) return q.norm() > 0 ? Vec3(point + q.normalized() * radius) : p;
  const double t = q.dot(axis);
  const Vec3 e = across_axis(q, axis);
  if (kind == Kind::Cylinder) return point + axis * t + e * radius;
  const Vec3 g = axis * std::cos(angle) + e * std::sin(angle);  // the generator through p
  return point + g * std::max(q.dot(g), 0.0);
}

Vec3 CurvedPrimitive::normal(const Vec3& p) const {
  const Vec3 q = p - point;
  if (kind == Kind::Sphere) return q.norm() > 0 ? Vec3(q.normalized()) : Vec3::UnitZ();
  const Vec3 e = across_axis(q, axis);
  if (kind == Kind::Cylinder) return e;
  return e * std::cos(angle) - axis * std::sin(angle);
}

CurvedSnapReport snap_to_curved(TriMesh& mesh, const std::vector<CurvedPrimitive>& surfaces,
                                const CurvedSnapOptions& o) {
  CurvedSnapReport r;
  VulkanCompute* vk = select_compute(o.device, &r.device);
  const std::vector<std::int32_t> vs = vertex_surfaces(mesh, surfaces, o, &r.triangles_on_surfaces);
  r.vertices_snapped = int(std::count_if(vs.begin(), vs.end(), [](std::int32_t k) { return k >= 0; }));
  r.mean_distance_before = mean_distance(mesh, surfaces, vs);
  if (r.vertices_snapped == 0) return r;
  // Float about the mesh's centre: local metres keep 0.1 mm in float, heights
  // of several hundred metres do not.
  Vec3 centre = Vec3::Zero();
  for (const Vec3& p : mesh.vertices) centre += p;
  centre /= double(mesh.vertices.size());
  std::vector<float> v;
  for (const Vec3& p : mesh.vertices)
    for (int k = 0; k < 3; ++k) v.push_back(static_cast<float>(p[k] - centre[k]));
  kernel_snap_curved(v, vs, kernel_surfaces(surfaces, centre), vk, o.threads);
  for (size_t i = 0; i < mesh.vertices.size(); ++i)
    if (vs[i] >= 0) mesh.vertices[i] = centre + Vec3(v[3 * i], v[3 * i + 1], v[3 * i + 2]);
  r.mean_distance_after = mean_distance(mesh, surfaces, vs);
  return r;
}

}  // namespace c3d

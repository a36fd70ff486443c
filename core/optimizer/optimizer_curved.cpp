// Snapping a mesh onto primitives (spheres, cylinders, cones, planes): seed
// 000's surface optimization for shapes whose surfaces are known exactly.
#include <algorithm>
#include <cmath>
#include <numeric>

#include "core/optimizer/height_field_eval.h"
#include "core/optimizer/mesh_subdivision.h"
#include "core/optimizer/optimizer.h"
#include "core/optimizer/optimizer_kernels.h"

namespace c3d {

namespace {

constexpr double kPi = 3.14159265358979323846;
// A surface holds points whose nearest point on it is this far past its span
// at most: where two bands of a profile meet at a slight kink, a point
// outside the kink projects past the ends of both.
constexpr double kSpanSlackM = 0.05;

// The unit direction from the axis to p, across it (any where p is on it).
Vec3 across_axis(const Vec3& q, const Vec3& axis) {
  const Vec3 radial = q - axis * q.dot(axis);
  return radial.norm() > 0 ? Vec3(radial.normalized()) : Vec3(axis.unitOrthogonal());
}

// What the kernel reads of the surfaces, about `centre` (as
// shaders/opt_snap_curved.comp lays it out): 12 floats per surface, and the
// height fields' knots and pole heights.
struct KernelSurfaces {
  std::vector<float> surfaces, heights;
};

void append_heights(const HeightFieldData& f, double centre_z, std::vector<float>& out) {
  for (double k : f.ku) out.push_back(static_cast<float>(k));
  for (double k : f.kv) out.push_back(static_cast<float>(k));
  for (double z : f.z) out.push_back(static_cast<float>(z - centre_z));
}

KernelSurfaces kernel_surfaces(const std::vector<CurvedPrimitive>& surfaces, const Vec3& centre) {
  KernelSurfaces out;
  for (const CurvedPrimitive& s : surfaces) {
    const double kind = double(int(s.kind));  // 0 sphere, 1 cylinder, 2 cone, 3 plane, 4 height field
    std::vector<double> fields;
    if (s.kind == CurvedPrimitive::Kind::HeightField) {
      const HeightFieldData& f = *s.heights;
      const Vec2 o = f.origin - centre.head<2>();
      fields = {o.x(), o.y(), 0.0, kind, f.e1.x(), f.e1.y(), double(out.heights.size()), 0.0,
                double(f.nu), double(f.nv), 0.0, 0.0};
      append_heights(f, centre.z(), out.heights);
    } else {
      const Vec3 c = s.point - centre;
      fields = {c.x(), c.y(), c.z(), kind, s.axis.x(), s.axis.y(), s.axis.z(), s.radius, std::cos(s.angle),
                std::sin(s.angle), 0.0, 0.0};
    }
    for (double x : fields) out.surfaces.push_back(static_cast<float>(x));
  }
  if (out.heights.empty()) out.heights.push_back(0);  // a buffer is never empty
  return out;
}

// Whether p's nearest point on s lies where s is part of the shape (a band
// of a profile ends where its step does; past its end it leaves the shape).
bool holds(const CurvedPrimitive& s, const Vec3& p) { return s.spans(s.project(p), kSpanSlackM); }

// The surface of each triangle (-1 none): the nearest whose normal agrees
// with its own, holding its centroid within reach.
std::vector<std::int32_t> triangle_surfaces(const TriMesh& mesh, const std::vector<CurvedPrimitive>& surfaces,
                                            const CurvedSnapOptions& o) {
  const double min_cos = std::cos(o.assign_angle_deg * kPi / 180);
  std::vector<std::int32_t> ts(mesh.triangles.size(), -1);
  for (size_t t = 0; t < ts.size(); ++t) {
    const auto& v = mesh.triangles[t];
    const Vec3 &a = mesh.vertices[size_t(v[0])], &b = mesh.vertices[size_t(v[1])], &c = mesh.vertices[size_t(v[2])];
    const Vec3 centroid = (a + b + c) / 3, n = (b - a).cross(c - a);
    if (n.norm() <= 0) continue;
    double nearest = o.assign_distance_m;
    for (size_t k = 0; k < surfaces.size(); ++k) {
      const double d = surfaces[k].distance(centroid);
      if (d <= nearest && holds(surfaces[k], centroid) &&
          std::abs(n.normalized().dot(surfaces[k].normal(centroid))) >= min_cos)
        nearest = d, ts[t] = std::int32_t(k);
    }
  }
  return ts;
}

// The surface p is snapped onto: the nearest of `candidates` that holds it,
// else the nearest of all that holds it within reach; -1 none.
std::int32_t vertex_surface(const Vec3& p, const std::vector<std::int32_t>& candidates,
                            const std::vector<CurvedPrimitive>& surfaces, double reach) {
  std::int32_t best = -1;
  for (std::int32_t k : candidates)
    if (holds(surfaces[size_t(k)], p) && (best < 0 || surfaces[size_t(k)].distance(p) < surfaces[size_t(best)].distance(p)))
      best = k;
  if (best >= 0) return best;
  double nearest = reach;
  for (size_t k = 0; k < surfaces.size(); ++k)
    if (surfaces[k].distance(p) <= nearest && holds(surfaces[k], p)) nearest = surfaces[k].distance(p), best = int(k);
  return best;
}

// Per vertex: the surface it is snapped onto (-1 none), from the surfaces of
// its triangles; a vertex none of whose triangles is on one (their normals
// tilted by noise, or bridging two surfaces) takes the nearest surface
// within reach. Counts the triangles on surfaces.
std::vector<std::int32_t> vertex_surfaces(const TriMesh& mesh, const std::vector<CurvedPrimitive>& surfaces,
                                          const CurvedSnapOptions& o, int* on_surfaces) {
  const std::vector<std::int32_t> ts = triangle_surfaces(mesh, surfaces, o);
  *on_surfaces = int(std::count_if(ts.begin(), ts.end(), [](std::int32_t k) { return k >= 0; }));
  std::vector<std::vector<std::int32_t>> candidates(mesh.vertices.size());
  std::vector<char> used(mesh.vertices.size(), 0);
  for (size_t t = 0; t < ts.size(); ++t)
    for (int v : mesh.triangles[t]) {
      used[size_t(v)] = 1;
      if (ts[t] >= 0) candidates[size_t(v)].push_back(ts[t]);
    }
  std::vector<std::int32_t> vs(mesh.vertices.size(), -1);
  for (size_t v = 0; v < vs.size(); ++v)
    if (used[v]) vs[v] = vertex_surface(mesh.vertices[v], candidates[v], surfaces, o.assign_distance_m);
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

// Each vertex with a surface moved onto it (kernel_snap_curved), in float
// about the mesh's centre: local metres keep 0.1 mm in float, heights of
// several hundred metres do not.
void snap(TriMesh& mesh, const std::vector<std::int32_t>& vs, const std::vector<CurvedPrimitive>& surfaces,
          VulkanCompute* vk, int threads) {
  Vec3 centre = Vec3::Zero();
  for (const Vec3& p : mesh.vertices) centre += p;
  centre /= double(mesh.vertices.size());
  std::vector<float> v;
  for (const Vec3& p : mesh.vertices)
    for (int k = 0; k < 3; ++k) v.push_back(static_cast<float>(p[k] - centre[k]));
  const KernelSurfaces k = kernel_surfaces(surfaces, centre);
  kernel_snap_curved(v, vs, k.surfaces, k.heights, vk, threads);
  for (size_t i = 0; i < mesh.vertices.size(); ++i)
    if (vs[i] >= 0) mesh.vertices[i] = centre + Vec3(v[3 * i], v[3 * i + 1], v[3 * i + 2]);
}

// How far the surfaces under a triangle's corners turn across it, rad: the
// largest angle between their normals there (0 with fewer than two on one).
double bending(const TriMesh& mesh, const std::array<int, 3>& t, const std::vector<CurvedPrimitive>& surfaces,
               const std::vector<std::int32_t>& vs) {
  std::vector<Vec3> normals;
  for (int v : t)
    if (vs[size_t(v)] >= 0) normals.push_back(surfaces[size_t(vs[size_t(v)])].normal(mesh.vertices[size_t(v)]));
  double worst = 0;
  for (size_t i = 0; i < normals.size(); ++i)
    for (size_t j = i + 1; j < normals.size(); ++j)
      worst = std::max(worst, std::acos(std::clamp(normals[i].dot(normals[j]), -1.0, 1.0)));
  return worst;
}

// Seed 000's surface junction rule: a triangle the surfaces under it turn
// across by more than the curvature threshold (a flat triangle cannot follow
// them: within a curved surface, or where two surfaces meet) is split at its
// edge midpoints, which are snapped onto the nearest of its corners'
// surfaces that holds them; once, and twice more where they turn by over
// ten times the threshold. Returns the triangles split.
int subdivide_by_bending(TriMesh& mesh, const std::vector<CurvedPrimitive>& surfaces, std::vector<std::int32_t>& vs,
                         const CurvedSnapOptions& o, VulkanCompute* vk) {
  const double threshold = o.curvature_threshold_deg * kPi / 180;
  int total = 0;
  for (int round = 1; round <= 3; ++round) {
    const double limit = round == 1 ? threshold : 10 * threshold;
    std::vector<char> marked(mesh.triangles.size(), 0);
    for (size_t t = 0; t < marked.size(); ++t) marked[t] = bending(mesh, mesh.triangles[t], surfaces, vs) > limit;
    if (std::none_of(marked.begin(), marked.end(), [](char m) { return m != 0; })) break;
    const std::vector<std::array<int, 3>> parents = mesh.triangles;
    const size_t old_vertices = mesh.vertices.size();
    std::vector<int> parent(mesh.triangles.size());
    std::iota(parent.begin(), parent.end(), 0);
    total += subdivide_marked(mesh, parent, marked);
    std::vector<std::vector<std::int32_t>> candidates(mesh.vertices.size() - old_vertices);
    for (size_t t = 0; t < mesh.triangles.size(); ++t)
      for (int v : mesh.triangles[t])
        if (size_t(v) >= old_vertices)
          for (int corner : parents[size_t(parent[t])])
            if (vs[size_t(corner)] >= 0) candidates[size_t(v) - old_vertices].push_back(vs[size_t(corner)]);
    vs.resize(mesh.vertices.size(), -1);
    for (size_t v = old_vertices; v < vs.size(); ++v)
      vs[v] = vertex_surface(mesh.vertices[v], candidates[v - old_vertices], surfaces, o.assign_distance_m);
    snap(mesh, vs, surfaces, vk, o.threads);
  }
  return total;
}

// The parameters of the point of a height field nearest p.
Vec2 nearest_on(const HeightFieldData& f, const Vec3& p) {
  const Vec2 q = f.uv(p.head<2>());
  Vec2 uv;
  nearest_parameters(f.ku.data(), f.nu, f.kv.data(), f.nv, f.z.data(), q.x(), q.y(), p.z(), uv.x(), uv.y());
  return uv;
}

HeightSample<double> sample(const HeightFieldData& f, const Vec2& uv) {
  return height_at(f.ku.data(), f.nu, f.kv.data(), f.nv, f.z.data(), uv.x(), uv.y());
}

}  // namespace

Vec3 CurvedPrimitive::project(const Vec3& p) const {
  if (kind == Kind::HeightField) {
    const Vec2 uv = nearest_on(*heights, p);
    const Vec2 plan = heights->plan(uv.x(), uv.y());
    return {plan.x(), plan.y(), sample(*heights, uv).h};
  }
  const Vec3 q = p - point;
  if (kind == Kind::Sphere) return q.norm() > 0 ? Vec3(point + q.normalized() * radius) : p;
  if (kind == Kind::Plane) return p - axis * q.dot(axis);
  const double t = q.dot(axis);
  const Vec3 e = across_axis(q, axis);
  if (kind == Kind::Cylinder) return point + axis * t + e * radius;
  const Vec3 g = axis * std::cos(angle) + e * std::sin(angle);  // the generator through p
  return point + g * std::max(q.dot(g), 0.0);
}

Vec3 CurvedPrimitive::normal(const Vec3& p) const {
  if (kind == Kind::HeightField) {
    const HeightSample<double> s = sample(*heights, nearest_on(*heights, p));
    const Vec2 down = s.hu * heights->e1 + s.hv * heights->e2();  // the slope in plan
    return Vec3(-down.x(), -down.y(), 1).normalized();
  }
  const Vec3 q = p - point;
  if (kind == Kind::Sphere) return q.norm() > 0 ? Vec3(q.normalized()) : Vec3::UnitZ();
  if (kind == Kind::Plane) return axis;
  const Vec3 e = across_axis(q, axis);
  if (kind == Kind::Cylinder) return e;
  return e * std::cos(angle) - axis * std::sin(angle);
}

bool CurvedPrimitive::spans(const Vec3& p, double slack) const {
  if (kind == Kind::HeightField) {
    const Vec2 uv = heights->uv(p.head<2>());
    const HeightFieldData& f = *heights;
    return uv.x() >= f.ku[3] - slack && uv.x() <= f.ku[size_t(f.nu)] + slack && uv.y() >= f.kv[3] - slack &&
           uv.y() <= f.kv[size_t(f.nv)] + slack;
  }
  if (span.isZero()) return true;
  const double t = (p - point).dot(span);
  return t >= span_lo - slack && t <= span_hi + slack;
}

CurvedSnapReport snap_to_curved(TriMesh& mesh, const std::vector<CurvedPrimitive>& surfaces,
                                const CurvedSnapOptions& o) {
  CurvedSnapReport r;
  VulkanCompute* vk = select_compute(o.device, &r.device);
  std::vector<std::int32_t> vs = vertex_surfaces(mesh, surfaces, o, &r.triangles_on_surfaces);
  r.mean_distance_before = mean_distance(mesh, surfaces, vs);
  if (std::none_of(vs.begin(), vs.end(), [](std::int32_t k) { return k >= 0; })) return r;
  snap(mesh, vs, surfaces, vk, o.threads);
  if (o.subdivide) r.triangles_subdivided = subdivide_by_bending(mesh, surfaces, vs, o, vk);
  r.vertices_snapped = int(std::count_if(vs.begin(), vs.end(), [](std::int32_t k) { return k >= 0; }));
  r.mean_distance_after = mean_distance(mesh, surfaces, vs);
  return r;
}

}  // namespace c3d

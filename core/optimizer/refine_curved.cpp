#include "core/optimizer/refine_curved.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/check/solid_check.h"
#include "core/optimizer/mesh_dense.h"
#include "core/optimizer/mesh_distance.h"
#include "core/optimizer/exact_surfaces.h"

namespace c3d {

namespace {

constexpr double kNearModelM = 0.5;       // a point this near the model is the building's
constexpr double kMinMeshRadiusM = 0.6;   // greedy projection's search radius: at least this,
constexpr double kMeshRadiusSpacings = 4; // and this many point spacings
constexpr double kCoveredNoises = 3;      // the mesh stands where the shape is this many noises from it
constexpr double kSampleStepM = 0.2;      // the exact shape sampled this finely for the Chamfer distance
constexpr double kSpanSlackM = 0.01;      // a surface reaches this far past where its step ends
constexpr int kMinTriangles = 10;

std::vector<Triangle3> model_triangles(const Building& b) {
  std::vector<Face> faces;
  for (const Element& e : b.elements) faces.insert(faces.end(), e.faces.begin(), e.faces.end());
  std::vector<Triangle3> out;
  for (const Triangle& t : triangulate(faces)) out.push_back({t.a, t.b, t.c});
  return out;
}

// Points spread evenly over the triangles, one per step x step of area (at
// least one each): the R2 low-discrepancy sequence folded into each triangle.
std::vector<Vec3> samples(const std::vector<Triangle3>& tris, double step) {
  constexpr double kA1 = 0.7548776662466927, kA2 = 0.5698402909980532;  // 1/g, 1/g^2 of the plastic number g
  std::vector<Vec3> out;
  for (const Triangle3& t : tris) {
    const double area = (t[1] - t[0]).cross(t[2] - t[0]).norm() / 2;
    const long n = std::max(1L, std::lround(area / (step * step)));
    for (long i = 0; i < n; ++i) {
      double u = std::fmod(0.5 + double(i) * kA1, 1.0), v = std::fmod(0.5 + double(i) * kA2, 1.0);
      if (u + v > 1) u = 1 - u, v = 1 - v;
      out.push_back(t[0] + u * (t[1] - t[0]) + v * (t[2] - t[0]));
    }
  }
  return out;
}

// The exact shape's surface nearest p among those that span it (its faces
// bound it: this is where they lie); none where none spans p.
const CurvedPrimitive* nearest_surface(const Vec3& p, const std::vector<CurvedPrimitive>& surfaces) {
  const CurvedPrimitive* nearest = nullptr;
  for (const CurvedPrimitive& s : surfaces)
    if (s.spans(p, kSpanSlackM) && (!nearest || s.distance(p) < nearest->distance(p))) nearest = &s;
  return nearest;
}

// The distance of p to the exact shape.
double to_shape(const Vec3& p, const std::vector<CurvedPrimitive>& surfaces) {
  const CurvedPrimitive* s = nearest_surface(p, surfaces);
  return s ? s->distance(p) : std::numeric_limits<double>::infinity();
}

// The scan's noise, robustly: the median distance of the points to the
// exact shape over that of a normal deviate's (0.674 sigma).
double noise(const std::vector<Vec3>& points, const std::vector<CurvedPrimitive>& surfaces) {
  std::vector<double> d;
  for (const Vec3& p : points) d.push_back(to_shape(p, surfaces));
  if (d.empty()) return 0;
  std::nth_element(d.begin(), d.begin() + long(d.size() / 2), d.end());
  return d[d.size() / 2] / 0.6745;
}

// The mesh without the points no triangle took (greedy projection keeps
// every point as a vertex).
void drop_unused_vertices(TriMesh& m) {
  std::vector<int> index(m.vertices.size(), -1);
  std::vector<Vec3> kept;
  for (auto& t : m.triangles)
    for (int& v : t) {
      if (index[size_t(v)] < 0) index[size_t(v)] = int(kept.size()), kept.push_back(m.vertices[size_t(v)]);
      v = index[size_t(v)];
    }
  m.vertices = std::move(kept);
}

double mean(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return v.empty() ? kNaN : s / double(v.size());
}

// Symmetric Chamfer distance of the mesh to the exact shape: the mean of the
// mesh's vertices' and centroids' distances to it, and of the distances of
// `covered` (points on it) to the mesh.
double chamfer(const TriMesh& mesh, const std::vector<CurvedPrimitive>& surfaces, const std::vector<Vec3>& covered,
               const DistanceOptions& o) {
  std::vector<double> to_exact;
  for (const Vec3& p : mesh.vertices) to_exact.push_back(to_shape(p, surfaces));
  for (const Triangle3& t : mesh.soup()) to_exact.push_back(to_shape((t[0] + t[1] + t[2]) / 3, surfaces));
  return (mean(to_exact) + mean(point_to_mesh_distances(covered, mesh.soup(), o))) / 2;
}

// The exact shape where the mesh stands: the model's samples moved onto its
// surfaces, those within `near.beyond_m` of the mesh. The Chamfer distance
// compares the two there, not the mesh's holes (the ground, flanks the air
// sees little of), which snapping does not fill.
std::vector<Vec3> shape_under_mesh(const std::vector<Triangle3>& model, const std::vector<CurvedPrimitive>& surfaces,
                                   const TriMesh& mesh, const DistanceOptions& near) {
  std::vector<Vec3> on_shape;
  for (const Vec3& p : samples(model, kSampleStepM))
    if (const CurvedPrimitive* s = nearest_surface(p, surfaces)) on_shape.push_back(s->project(p));
  const std::vector<double> gap = point_to_mesh_distances(on_shape, mesh.soup(), near);
  std::vector<Vec3> covered;
  for (size_t i = 0; i < on_shape.size(); ++i)
    if (gap[i] <= near.beyond_m) covered.push_back(on_shape[i]);
  return covered;
}

}  // namespace

RefinedMesh refine_curved(const Building& b, const std::vector<Vec3>& points, double spacing,
                          ComputeDevice device) {
  RefinedMesh r;
  const std::vector<CurvedPrimitive> surfaces = exact_surfaces(b.exact);
  const std::vector<Triangle3> model = model_triangles(b);
  if (surfaces.empty() || model.empty()) return r;
  DistanceOptions d;
  d.device = device;
  d.threads = 1;  // parcels run side by side
  std::vector<Vec3> own;
  DistanceOptions near = d;  // whether near, not how far: a far point searches many cells
  near.beyond_m = kNearModelM;
  const std::vector<double> to_model = point_to_mesh_distances(points, model, near);
  for (size_t i = 0; i < points.size(); ++i)
    if (to_model[i] <= kNearModelM) own.push_back(points[i]);
  DenseOptions dense;
  dense.greedy_radius_m = std::max(kMinMeshRadiusM, kMeshRadiusSpacings * spacing);
  r.mesh = greedy_mesh(own, dense);
  drop_unused_vertices(r.mesh);
  if (int(r.mesh.triangles.size()) < kMinTriangles) return {};
  near.beyond_m = kCoveredNoises * noise(own, surfaces);
  const std::vector<Vec3> covered = shape_under_mesh(model, surfaces, r.mesh, near);
  MeshRefinement& e = r.effect;
  e.triangles = int(r.mesh.triangles.size());
  e.chamfer_before_m = chamfer(r.mesh, surfaces, covered, d);
  e.cloud_before_m = mean(point_to_mesh_distances(own, r.mesh.soup(), d));
  CurvedSnapOptions snap;
  snap.device = device;
  const CurvedSnapReport rep = snap_to_curved(r.mesh, surfaces, snap);
  e.snapped_share = double(rep.vertices_snapped) / double(r.mesh.vertices.size());
  e.chamfer_after_m = chamfer(r.mesh, surfaces, covered, d);
  e.cloud_after_m = mean(point_to_mesh_distances(own, r.mesh.soup(), d));
  return r;
}

}  // namespace c3d

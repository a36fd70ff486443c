// The optimizer's surface snapping onto curved primitives (seed 000): the
// dense mesh of a curved roof's points, snapped onto the surface the
// primitive search or the free-form fit fitted, lies at least 50 % closer to the true surface
// (Chamfer), and the Vulkan kernel moves each vertex where the CPU
// reference does, within 1e-5 m.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <iostream>
#include <random>
#include <set>

#include "core/geometry/geometry.h"
#include "core/optimizer/mesh_dense.h"
#include "core/optimizer/mesh_distance.h"
#include "core/optimizer/vulkan_compute.h"
#include "core/optimizer/exact_surfaces.h"
#include "core/optimizer/height_field_eval.h"
#include "core/primitives/height_field.h"
#include "core/primitives/primitives.h"
#include "core/synthetic/sample_town.h"
#include "tests/test_support.h"

using namespace c3d;

namespace {

struct CurvedRoof {
  SampleLayout layout;
  std::vector<Vec3> points;      // its roof points, local
  std::vector<Triangle3> truth;  // its exact roof's faces (within 2 mm of the surface)
};

const std::set<SampleLayout> kPrimitiveRoofs{SampleLayout::Vault, SampleLayout::GroundVault, SampleLayout::Dome,
                                             SampleLayout::ShallowDome, SampleLayout::Cone};
const std::set<SampleLayout> kFreeFormRoofs{SampleLayout::Saddle, SampleLayout::Wave};

// The buildings of the curved town whose whole roof is one curved surface
// of the kinds `whole`.
std::vector<CurvedRoof> curved_roofs(const std::set<SampleLayout>& whole = kPrimitiveRoofs) {
  SampleOptions opt;
  opt.curved = true;
  opt.parcels = 10;
  opt.seed = 7;
  const SampleTown town = make_sample_town(opt);
  std::vector<CurvedRoof> out;
  for (size_t i = 0; i < town.parcels.size(); ++i) {
    if (!whole.count(town.layouts[i])) continue;
    CurvedRoof r{town.layouts[i], {}, {}};
    for (size_t k = 0; k < town.cloud.points.size(); ++k)
      if (town.cloud.classes[k] == 6 &&
          in_ring_plan(town.parcels[i].shape.front().outer, Vec2(town.cloud.points[k].head<2>())))
        r.points.push_back(town.cloud.points[k] - town.frame.origin);
    for (const Element& e : town.truth[i][0].model.elements)
      if (e.type == ElementType::Roof)
        for (const Face& f : e.faces)
          for (size_t j = 1; j + 1 < f.ring.size(); ++j) r.truth.push_back({f.ring[0], f.ring[j], f.ring[j + 1]});
    out.push_back(std::move(r));
  }
  return out;
}

// The height field fitted to a free-form roof's points (the sample's 3 cm
// noise, 40 points/m2), over their plan.
CurvedPrimitive fitted_height_field(const std::vector<Vec3>& points) {
  Vec2 lo(1e9, 1e9), hi(-1e9, -1e9);
  for (const Vec3& p : points) lo = lo.cwiseMin(p.head<2>()), hi = hi.cwiseMax(p.head<2>());
  const Ring2 cover{lo, Vec2(hi.x(), lo.y()), hi, Vec2(lo.x(), hi.y())};
  const auto fit = fit_height_field(points, 0.03, 1 / std::sqrt(40.0), cover, Vec2::UnitX());
  EXPECT_TRUE(fit.has_value());
  CurvedPrimitive s;
  s.kind = CurvedPrimitive::Kind::HeightField;
  s.heights = std::make_shared<const HeightFieldData>(height_field_data(fit->surface).value());
  return s;
}

// The dense mesh of the points and the curved surface fitted to them.
std::pair<TriMesh, CurvedPrimitive> mesh_and_surface(const CurvedRoof& roof) {
  TriMesh mesh = greedy_mesh(roof.points, DenseOptions{});
  if (kFreeFormRoofs.count(roof.layout)) return {mesh, fitted_height_field(roof.points)};
  const PrimitiveFit fit = find_curved_surfaces(roof.points, {});
  EXPECT_EQ(fit.curved.size(), 1u);
  return {mesh, snap_target(fit.curved.at(0)).value()};
}

}  // namespace

// Chamfer distance of a mesh to the true surface where the mesh stands: the
// mean of the mesh's distances to the truth (its vertices and centroids) and
// the truth's to the mesh (samples every 10 cm), over the truth samples within
// `covered` of the unrefined mesh. Snapping moves the mesh onto the surface;
// it does not fill the mesh's holes (steep flanks the air sees little of),
// whose distance would hide its effect; coverage is the mesh's own measure.
struct Chamfer {
  double to_truth = 0, from_truth = 0;
  double value() const { return (to_truth + from_truth) / 2; }
};

std::vector<Vec3> samples(const std::vector<Triangle3>& tris, double step) {
  std::vector<Vec3> out;
  for (const Triangle3& t : tris) {
    const int n = std::max(1, int(std::ceil(std::max((t[1] - t[0]).norm(), (t[2] - t[0]).norm()) / step)));
    for (int i = 0; i <= n; ++i)
      for (int j = 0; i + j <= n; ++j) out.push_back(t[0] + (t[1] - t[0]) * i / n + (t[2] - t[0]) * j / n);
  }
  return out;
}

std::vector<double> distances(const std::vector<Vec3>& points, const std::vector<Triangle3>& mesh) {
  DistanceOptions o;
  o.device = ComputeDevice::Cpu;  // the reference, on every core
  return point_to_mesh_distances(points, mesh, o);
}

double mean(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return v.empty() ? 0 : s / double(v.size());
}

Chamfer chamfer_where_covered(const TriMesh& mesh, const std::vector<Vec3>& truth_samples,
                              const std::vector<Triangle3>& truth) {
  std::vector<Vec3> own = mesh.vertices;
  for (const Triangle3& t : mesh.soup()) own.push_back((t[0] + t[1] + t[2]) / 3);
  return {mean(distances(own, truth)), mean(distances(truth_samples, mesh.soup()))};
}

// Onto primitives (vault, dome, ground vault, cone, shallow dome) and onto
// the B-spline height fields of free-form roofs (saddle, wave).
TEST(OptimizerCurved, SnappingHalvesTheChamferToTheTrueSurface) {
  constexpr double kCoveredM = 0.1;  // 3.3 times the scan's noise
  std::vector<CurvedRoof> roofs = curved_roofs(), free_form = curved_roofs(kFreeFormRoofs);
  ASSERT_EQ(roofs.size(), 5u);
  ASSERT_EQ(free_form.size(), 2u);
  roofs.insert(roofs.end(), free_form.begin(), free_form.end());
  for (const CurvedRoof& roof : roofs) {
    auto [mesh, surface] = mesh_and_surface(roof);
    ASSERT_GT(mesh.triangles.size(), 100u);
    std::vector<Vec3> covered;
    const std::vector<Vec3> all = samples(roof.truth, 0.1);
    const std::vector<double> gap = distances(all, mesh.soup());
    for (size_t i = 0; i < all.size(); ++i)
      if (gap[i] <= kCoveredM) covered.push_back(all[i]);
    const Chamfer before = chamfer_where_covered(mesh, covered, roof.truth);
    CurvedSnapOptions o;
    o.device = ComputeDevice::Cpu;
    const CurvedSnapReport r = snap_to_curved(mesh, {surface}, o);
    const Chamfer after = chamfer_where_covered(mesh, covered, roof.truth);
    const std::string what = std::string(to_string(roof.layout)) + ": Chamfer " + std::to_string(before.value()) +
                             " -> " + std::to_string(after.value()) + " m, truth covered " +
                             std::to_string(100.0 * double(covered.size()) / double(all.size())) + " %";
    std::cout << what << " (mesh to truth " << before.to_truth << " -> " << after.to_truth << ", truth to mesh "
              << before.from_truth << " -> " << after.from_truth << ")\n";
    EXPECT_GT(r.vertices_snapped, int(0.9 * double(mesh.vertices.size()))) << what;
    EXPECT_LT(r.mean_distance_after, 1e-4) << what;
    EXPECT_LE(after.value(), 0.5 * before.value()) << what;
  }
}

TEST(OptimizerCurved, VulkanSnapsAsTheCpuReference) {
  std::string why;
  C3D_NEED(shared_vulkan(&why), "no Vulkan: " << why);
  std::vector<CurvedRoof> roofs = curved_roofs(), free_form = curved_roofs(kFreeFormRoofs);
  roofs.insert(roofs.end(), free_form.begin(), free_form.end());
  for (const CurvedRoof& roof : roofs) {
    auto [cpu, surface] = mesh_and_surface(roof);
    TriMesh gpu = cpu;
    CurvedSnapOptions o;
    o.device = ComputeDevice::Cpu;
    snap_to_curved(cpu, {surface}, o);
    o.device = ComputeDevice::Vulkan;
    const CurvedSnapReport r = snap_to_curved(gpu, {surface}, o);
    EXPECT_NE(r.device.find("Vulkan"), std::string::npos) << r.device;
    ASSERT_EQ(cpu.vertices.size(), gpu.vertices.size()) << "the same triangles split";
    double worst = 0;
    for (size_t i = 0; i < cpu.vertices.size(); ++i) worst = std::max(worst, (cpu.vertices[i] - gpu.vertices[i]).norm());
    EXPECT_LE(worst, 1e-5) << int(roof.layout);
  }
}

namespace {

using Step = ProfileStep;

// A hemisphere on a round drum of radius r and height h, about (3, 4, 0).
ShapePart dome_on_drum(double r, double h) {
  ShapePart p;
  p.revolve = true;
  p.origin = Vec3(3, 4, 0);
  p.steps = {{Step::Kind::Line, {}, Vec2(r, 0)},
             {Step::Kind::Line, {}, Vec2(r, h)},
             {Step::Kind::Arc, {Vec2(r * std::cos(M_PI / 4), h + r * std::sin(M_PI / 4))}, Vec2(0, h + r)}};
  return p;
}

// A barrel vault of half-width w on walls of height h, length l along y.
ShapePart vault_on_walls(double w, double h, double l) {
  ShapePart p;
  p.path = Vec3(0, l, 0);
  p.start = Vec2(-w, 0);
  p.steps = {{Step::Kind::Line, {}, Vec2(w, 0)},
             {Step::Kind::Line, {}, Vec2(w, h)},
             {Step::Kind::Arc, {Vec2(0, h + w)}, Vec2(-w, h)}};
  return p;
}

// An onion's bulb as a spline through a few points, on a drum of radius r.
ShapePart bulb_on_drum(double r, double h) {
  ShapePart p = dome_on_drum(r, h);
  p.steps.back() = {Step::Kind::Spline, {Vec2(1.15 * r, h + 1), Vec2(0.6 * r, h + 2.5)}, Vec2(0, h + 3.5)};
  return p;
}

// The nearest surface to p among those spanning it, and its distance.
std::pair<int, double> nearest_surface(const std::vector<CurvedPrimitive>& s, const Vec3& p) {
  std::pair<int, double> best{-1, 1e9};
  for (size_t k = 0; k < s.size(); ++k)
    if (s[k].spans(p, 0) && s[k].distance(p) < best.second) best = {int(k), s[k].distance(p)};
  return best;
}

// A triangle grid over f(s, t) for s, t in [0, 1], its vertices moved by up
// to `noise` along z.
TriMesh noisy_grid(const std::function<Vec3(double, double)>& f, int n, double noise, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-noise, noise);
  TriMesh m;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) m.vertices.push_back(f(double(i) / n, double(j) / n) + Vec3(0, 0, u(rng)));
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const int a = i * (n + 1) + j, b = a + 1, c = a + n + 1, d = c + 1;
      m.triangles.push_back({a, c, d});
      m.triangles.push_back({a, d, b});
    }
  return m;
}

}  // namespace

// Each profile step of an exact shape becomes the surface it sweeps: a
// point of the true shape lies on its own surface (ground, drum, dome; walls,
// vault, end caps; the bulb's band of cones), which spans it.
TEST(OptimizerCurved, ExactShapeSurfacesHoldTheirPoints) {
  const double r = 5, h = 4, w = 3, l = 12;
  const std::vector<CurvedPrimitive> dome = exact_surfaces(ExactShape{{dome_on_drum(r, h)}});
  using K = CurvedPrimitive::Kind;
  for (double a = 0; a < 2 * M_PI; a += 0.7) {
    const Vec3 centre(3, 4, 0), out(std::cos(a), std::sin(a), 0);
    for (const auto& [p, kind] : std::vector<std::pair<Vec3, K>>{
             {centre + 0.5 * r * out, K::Plane},
             {centre + r * out + Vec3(0, 0, 0.3 * h), K::Cylinder},
             {centre + Vec3(0, 0, h) + r * (std::cos(0.6) * out + Vec3(0, 0, std::sin(0.6))), K::Sphere}}) {
      const auto [k, d] = nearest_surface(dome, p);
      ASSERT_GE(k, 0);
      EXPECT_EQ(dome[size_t(k)].kind, kind);
      EXPECT_LT(d, 1e-9);
    }
  }
  const std::vector<CurvedPrimitive> vault = exact_surfaces(ExactShape{{vault_on_walls(w, h, l)}});
  for (const auto& [p, kind] : std::vector<std::pair<Vec3, K>>{
           {Vec3(w, 5, 1), K::Plane},
           {Vec3(w * std::cos(1.0), 7, h + w * std::sin(1.0)), K::Cylinder},
           {Vec3(0.5, 0, h + 1), K::Plane},
           {Vec3(-0.5, l, 2), K::Plane}}) {
    const auto [k, d] = nearest_surface(vault, p);
    ASSERT_GE(k, 0);
    EXPECT_EQ(vault[size_t(k)].kind, kind);
    EXPECT_LT(d, 1e-9);
  }
  EXPECT_FALSE(vault[size_t(nearest_surface(vault, Vec3(w * std::cos(1.0), 7, h + w * std::sin(1.0))).first)]
                   .spans(Vec3(0, l + 1, h + w), 0))
      << "the vault ends at its end walls";
  const ShapePart bulb = bulb_on_drum(r, h);
  const std::vector<CurvedPrimitive> onion = exact_surfaces(ExactShape{{bulb}});
  std::vector<Vec2> line{Vec2(r, h)};
  line.insert(line.end(), bulb.steps.back().through.begin(), bulb.steps.back().through.end());
  line.push_back(bulb.steps.back().to);
  for (size_t k = 1; k < line.size(); ++k) {
    const Vec2 q = (line[k - 1] + line[k]) / 2;
    const auto [i, d] = nearest_surface(onion, Vec3(3 + q.x() * std::cos(2.0), 4 + q.x() * std::sin(2.0), q.y()));
    ASSERT_GE(i, 0);
    EXPECT_EQ(onion[size_t(i)].kind, K::Cone);
    EXPECT_LT(d, 1e-9);
  }
}

// Planes and cones snap on Vulkan as on the CPU: a noisy vault with its end
// wall, and a noisy bulb, each onto its exact shape's surfaces.
TEST(OptimizerCurved, VulkanSnapsOntoExactShapesAsTheCpuReference) {
  std::string why;
  C3D_NEED(shared_vulkan(&why), "no Vulkan: " << why);
  const double r = 5, h = 4, w = 3, l = 12;
  const ShapePart bulb = bulb_on_drum(r, h);
  const std::vector<std::pair<TriMesh, ExactShape>> cases = {
      {noisy_grid([&](double s, double t) { return Vec3(w * std::cos(M_PI * s), l * t, h + w * std::sin(M_PI * s)); },
                  40, 0.03, 1),
       ExactShape{{vault_on_walls(w, h, l)}}},
      {noisy_grid([&](double s, double t) { return Vec3((2 * s - 1) * w, 0.02 * t, t * h); }, 20, 0.03, 2),
       ExactShape{{vault_on_walls(w, h, l)}}},
      {noisy_grid([&](double s, double t) {  // along the bulb's first two spans
         const Vec2 q = t < 0.5 ? Vec2(Vec2(r, h) + 2 * t * (bulb.steps.back().through[0] - Vec2(r, h)))
                                : Vec2(bulb.steps.back().through[0] +
                                       (2 * t - 1) * (bulb.steps.back().through[1] - bulb.steps.back().through[0]));
         return Vec3(3 + q.x() * std::cos(2 * M_PI * s), 4 + q.x() * std::sin(2 * M_PI * s), q.y());
       }, 40, 0.03, 3),
       ExactShape{{bulb}}}};
  for (const auto& [mesh, shape] : cases) {
    TriMesh cpu = mesh, gpu = mesh;
    CurvedSnapOptions o;
    o.device = ComputeDevice::Cpu;
    const CurvedSnapReport c = snap_to_curved(cpu, exact_surfaces(shape), o);
    o.device = ComputeDevice::Vulkan;
    const CurvedSnapReport g = snap_to_curved(gpu, exact_surfaces(shape), o);
    EXPECT_NE(g.device.find("Vulkan"), std::string::npos) << g.device;
    EXPECT_GT(c.vertices_snapped, int(0.9 * double(mesh.vertices.size())));
    EXPECT_LT(c.mean_distance_after, 1e-4);
    ASSERT_EQ(cpu.vertices.size(), gpu.vertices.size()) << "the same triangles split";
    double worst = 0;
    for (size_t i = 0; i < cpu.vertices.size(); ++i) worst = std::max(worst, (cpu.vertices[i] - gpu.vertices[i]).norm());
    EXPECT_LE(worst, 1e-5);
  }
}

// Seed 000's surface junction rule: where two surfaces meet at a crease (a
// ridge), the triangles straddling it are split and their new vertices
// snapped, so the mesh comes at least twice as near the crease as a mesh only
// snapped.
TEST(OptimizerCurved, SubdivisionFollowsACrease) {
  const double w = 3, h = 4, l = 6;
  ShapePart gable;  // a 45-degree gable roof swept along y
  gable.path = Vec3(0, l, 0);
  gable.start = Vec2(-w, 0);
  gable.steps = {{Step::Kind::Line, {}, Vec2(w, 0)},
                 {Step::Kind::Line, {}, Vec2(w, h)},
                 {Step::Kind::Line, {}, Vec2(0, h + w)},
                 {Step::Kind::Line, {}, Vec2(-w, h)}};
  const TriMesh roof =
      noisy_grid([&](double s, double t) { const double x = (2 * s - 1) * w; return Vec3(x, l * t, h + w - std::abs(x)); },
                 7, 0.0, 4);  // the ridge runs through the middle of a column of cells
  std::vector<Vec3> ridge;
  for (double y = 0.5; y < l - 0.5; y += 0.25) ridge.emplace_back(0, y, h + w);
  double gap[2];
  for (int subdivide = 0; subdivide < 2; ++subdivide) {
    TriMesh m = roof;
    CurvedSnapOptions o;
    o.device = ComputeDevice::Cpu;
    o.subdivide = subdivide == 1;
    const CurvedSnapReport r = snap_to_curved(m, exact_surfaces(ExactShape{{gable}}), o);
    EXPECT_EQ(r.triangles_subdivided > 0, o.subdivide);
    gap[subdivide] = mean(distances(ridge, m.soup()));
  }
  EXPECT_GT(gap[0], 0.2) << "a chord cuts the ridge";
  EXPECT_LE(gap[1], 0.5 * gap[0]) << gap[0] << " -> " << gap[1];
}

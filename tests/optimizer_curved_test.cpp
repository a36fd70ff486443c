// The optimizer's surface snapping onto curved primitives (seed 000): the
// dense mesh of a curved roof's points, snapped onto the surface the
// primitive search fitted, lies at least 50 % closer to the true surface
// (Chamfer), and the Vulkan kernel moves each vertex where the CPU
// reference does, within 1e-5 m.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <set>

#include "core/geometry/geometry.h"
#include "core/optimizer/mesh_dense.h"
#include "core/optimizer/mesh_distance.h"
#include "core/optimizer/vulkan_compute.h"
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

// The buildings of the curved town whose whole roof is one curved surface.
std::vector<CurvedRoof> curved_roofs() {
  SampleOptions opt;
  opt.curved = true;
  opt.parcels = 8;
  opt.seed = 7;
  const SampleTown town = make_sample_town(opt);
  const std::set<SampleLayout> whole{SampleLayout::Vault, SampleLayout::GroundVault, SampleLayout::Dome,
                                     SampleLayout::ShallowDome, SampleLayout::Cone};
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

// The dense mesh of the points and the curved surface fitted to them.
std::pair<TriMesh, CurvedPrimitive> mesh_and_surface(const CurvedRoof& roof) {
  const PrimitiveFit fit = find_curved_surfaces(roof.points, {});
  EXPECT_EQ(fit.curved.size(), 1u);
  return {greedy_mesh(roof.points, DenseOptions{}), snap_target(fit.curved.at(0)).value()};
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

TEST(OptimizerCurved, SnappingHalvesTheChamferToTheTrueSurface) {
  constexpr double kCoveredM = 0.1;  // 3.3 times the scan's noise
  const std::vector<CurvedRoof> roofs = curved_roofs();
  ASSERT_EQ(roofs.size(), 5u);
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
  for (const CurvedRoof& roof : curved_roofs()) {
    auto [cpu, surface] = mesh_and_surface(roof);
    TriMesh gpu = cpu;
    CurvedSnapOptions o;
    o.device = ComputeDevice::Cpu;
    snap_to_curved(cpu, {surface}, o);
    o.device = ComputeDevice::Vulkan;
    const CurvedSnapReport r = snap_to_curved(gpu, {surface}, o);
    EXPECT_NE(r.device.find("Vulkan"), std::string::npos) << r.device;
    double worst = 0;
    for (size_t i = 0; i < cpu.vertices.size(); ++i) worst = std::max(worst, (cpu.vertices[i] - gpu.vertices[i]).norm());
    EXPECT_LE(worst, 1e-5) << int(roof.layout);
  }
}

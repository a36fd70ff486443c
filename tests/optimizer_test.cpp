// Optimizer: CPU reference vs Vulkan (lavapipe under ctest), energy decrease,
// and the synthetic noisy gable roof (Chamfer drop, junction accuracy).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

#include "core/optimizer/optimizer.h"
#include "core/optimizer/optimizer_kernels.h"
#include "core/optimizer/vulkan_compute.h"
#include "tests/test_support.h"

using namespace c3d;

namespace {

constexpr double kRidgeX = 0.13;  // off the grid lines: triangles straddle the ridge

double roof_z(double x) { return 3.0 - 0.5 * std::fabs(x - kRidgeX); }

PrimitivePlane plane_through(Vec3 n, const Vec3& p) {
  n.normalize();
  return PrimitivePlane{n, -n.dot(p)};
}

// 10 m x 10 m gable roof on a 0.2 m grid, 3 cm noise per axis.
ConstrainedMesh noisy_gable(double noise = 0.03, double step = 0.2) {
  ConstrainedMesh cm;
  const int n = static_cast<int>(std::lround(10.0 / step));
  std::mt19937 rng(42);
  std::normal_distribution<double> g(0.0, noise);
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      double x = -5 + i * step, y = j * step;
      cm.mesh.vertices.push_back(Vec3(x + g(rng), y + g(rng), roof_z(x) + g(rng)));
    }
  cm.planes = {plane_through(Vec3(-0.5, 0, 1), Vec3(kRidgeX, 0, 3)),
               plane_through(Vec3(0.5, 0, 1), Vec3(kRidgeX, 0, 3))};
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      int a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
      for (std::array<int, 3> t : {std::array<int, 3>{a, b, d}, std::array<int, 3>{a, d, c}}) {
        double cx = -5 + step * ((t[0] % (n + 1)) + (t[1] % (n + 1)) + (t[2] % (n + 1))) / 3.0;
        cm.mesh.triangles.push_back(t);
        cm.tri_plane.push_back(cx < kRidgeX ? 0 : 1);
      }
    }
  cm.lines = {intersect_planes(cm.planes[0], cm.planes[1], 0, 1)};
  return cm;
}

std::vector<Triangle3> true_roof() {
  Vec3 r0(kRidgeX, 0, 3), r1(kRidgeX, 10, 3);
  Vec3 l0(-5, 0, roof_z(-5)), l1(-5, 10, roof_z(-5)), e0(5, 0, roof_z(5)), e1(5, 10, roof_z(5));
  return {{l0, r0, r1}, {l0, r1, l1}, {r0, e0, e1}, {r0, e1, r1}};
}

bool have_vulkan() { return shared_vulkan() != nullptr; }

OptimizerOptions opts(ComputeDevice d) {
  OptimizerOptions o;
  o.device = d;
  return o;
}

void expect_same_vertices(const ConstrainedMesh& a, const ConstrainedMesh& b) {
  ASSERT_EQ(a.mesh.vertices.size(), b.mesh.vertices.size());
  ASSERT_EQ(a.mesh.triangles, b.mesh.triangles);
  double worst = 0;
  for (std::size_t i = 0; i < a.mesh.vertices.size(); ++i)
    worst = std::max(worst, (a.mesh.vertices[i] - b.mesh.vertices[i]).norm());
  EXPECT_LT(worst, 1e-5);
}

// Random state touching every branch of the kernels.
KernelState random_state(int nv, int nt) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-10.f, 10.f);
  KernelState s;
  for (int i = 0; i < 3 * nv; ++i) s.v.push_back(u(rng));
  for (int i = 0; i < 3 * nt; ++i) s.tri.push_back(rng() % nv);
  for (int k = 0; k < 3; ++k) {
    Eigen::Vector3f n(u(rng), u(rng), u(rng));
    n.normalize();
    s.planes.insert(s.planes.end(), {n.x(), n.y(), n.z(), u(rng)});
    Eigen::Vector3f d(u(rng), u(rng), u(rng));
    d.normalize();
    s.lines.insert(s.lines.end(), {u(rng), u(rng), u(rng), 0.f, d.x(), d.y(), d.z(), 0.f});
  }
  for (int i = 0; i < nv; ++i) {
    s.vplane.push_back(static_cast<int>(rng() % 4) - 1);
    s.vline.push_back(static_cast<int>(rng() % 5) - 2 < 0 ? -1 : static_cast<int>(rng() % 3));
    s.weight.push_back(0.5f + static_cast<float>(rng() % 3));
  }
  for (int t = 0; t < nt; ++t) s.tplane.push_back(static_cast<int>(rng() % 4) - 1);
  return s;
}

}  // namespace

TEST(OptimizerKernels, CpuAndVulkanAgree) {
  C3D_NEED(have_vulkan(), "no Vulkan device");
  VulkanCompute* vk = shared_vulkan();
  KernelState s = random_state(5000, 8000);

  std::vector<float> ec, eg;
  kernel_energy(s, ec, nullptr);
  kernel_energy(s, eg, vk);
  ASSERT_EQ(ec.size(), eg.size());
  for (std::size_t i = 0; i < ec.size(); ++i) EXPECT_NEAR(ec[i], eg[i], 1e-5 * (1 + ec[i]));

  std::vector<std::int32_t> vcl(s.vertex_count());
  std::vector<float> xf;
  for (int c = 0; c < 3; ++c) {
    Eigen::Matrix3f R = Eigen::AngleAxisf(0.1f * (c + 1), Eigen::Vector3f(1, 2, 3).normalized()).toRotationMatrix();
    for (int r = 0; r < 3; ++r)
      for (int k = 0; k < 3; ++k) xf.push_back(R(r, k));
    xf.insert(xf.end(), {0.1f * c, -0.2f, 0.3f});
  }
  for (std::size_t i = 0; i < vcl.size(); ++i) vcl[i] = static_cast<int>(i % 4) - 1;
  KernelState a = s, b = s;
  kernel_transform(a, vcl, xf, nullptr);
  kernel_transform(b, vcl, xf, vk);
  for (std::size_t i = 0; i < a.v.size(); ++i) EXPECT_NEAR(a.v[i], b.v[i], 1e-5);

  std::vector<std::uint32_t> tasks;
  for (std::uint32_t i = 0; i < s.vertex_count(); i += 2) tasks.push_back(i);
  a = s, b = s;
  kernel_refine(a, tasks, static_cast<std::uint32_t>(tasks.size() / 3), nullptr);
  kernel_refine(b, tasks, static_cast<std::uint32_t>(tasks.size() / 3), vk);
  for (std::size_t i = 0; i < a.v.size(); ++i) EXPECT_NEAR(a.v[i], b.v[i], 1e-5);

  float vp[16] = {0.1f, 0, 0, 0, 0, 0.1f, 0, 0, 0, 0, 0.1f, 0, 0, 0, 0, 1};
  float eye[3] = {0, 0, 30};
  std::vector<std::uint32_t> fc, fg;
  kernel_view_select(s, vp, eye, 0.5f, fc, nullptr);
  kernel_view_select(s, vp, eye, 0.5f, fg, vk);
  EXPECT_EQ(fc, fg);
  EXPECT_GT(std::count(fc.begin(), fc.end(), 1u), 100);
}

TEST(OptimizerKernels, MultiThreadedCpuMatchesSingle) {
  KernelState s = random_state(20000, 100);
  std::vector<float> a, b;
  kernel_energy(s, a, nullptr, 1);
  kernel_energy(s, b, nullptr, 4);
  EXPECT_EQ(a, b);
}

TEST(Optimizer, NoisyGableRoofCpu) {
  ConstrainedMesh noisy = noisy_gable();
  const double before = chamfer_distance(noisy.mesh.soup(), true_roof(), {ComputeDevice::Cpu});
  ConstrainedMesh cm = noisy;
  OptimizeReport r = optimize_mesh(cm, opts(ComputeDevice::Cpu));
  EXPECT_NE(r.device.find("CPU"), std::string::npos);
  ASSERT_GE(r.energy.size(), 3u);
  for (std::size_t i = 1; i < r.energy.size(); ++i) EXPECT_LT(r.energy[i], r.energy[i - 1]);
  EXPECT_LT(r.energy.back(), 1e-3 * r.energy.front());
  const double after = chamfer_distance(cm.mesh.soup(), true_roof(), {ComputeDevice::Cpu});
  EXPECT_LT(after, 0.5 * before) << "Chamfer before " << before << " after " << after;
  EXPECT_GT(r.triangles_split, 0);
  EXPECT_GT(r.junction_vertices, 40);
  EXPECT_LT(r.max_line_distance, 1e-3);
  EXPECT_LT(r.max_plane_distance, 1e-4);
  // Every vertex where plane-0 and plane-1 triangles meet is on the ridge line.
  std::vector<int> mask(cm.mesh.vertices.size(), 0);
  for (std::size_t t = 0; t < cm.mesh.triangles.size(); ++t)
    for (int v : cm.mesh.triangles[t]) mask[v] |= 1 << cm.tri_plane[t];
  int junctions = 0;
  for (std::size_t v = 0; v < mask.size(); ++v)
    if (mask[v] == 3) {
      ++junctions;
      EXPECT_LT(cm.lines[0].distance(cm.mesh.vertices[v]), 1e-3);
    }
  EXPECT_GT(junctions, 40);
}

TEST(Optimizer, NoisyGableRoofVulkanMatchesCpu) {
  C3D_NEED(have_vulkan(), "no Vulkan device");
  ConstrainedMesh cpu = noisy_gable(), gpu = noisy_gable();
  OptimizeReport rc = optimize_mesh(cpu, opts(ComputeDevice::Cpu));
  OptimizeReport rg = optimize_mesh(gpu, opts(ComputeDevice::Vulkan));
  EXPECT_NE(rg.device.find("Vulkan"), std::string::npos) << rg.device;
  expect_same_vertices(cpu, gpu);
  ASSERT_EQ(rc.energy.size(), rg.energy.size());
  for (std::size_t i = 0; i < rc.energy.size(); ++i)
    EXPECT_NEAR(rc.energy[i], rg.energy[i], 1e-4 * (1 + rc.energy[i]));
  for (std::size_t i = 1; i < rg.energy.size(); ++i) EXPECT_LT(rg.energy[i], rg.energy[i - 1]);
  EXPECT_LT(rg.max_line_distance, 1e-3);
}

TEST(Optimizer, ViewDependentIncremental) {
  std::vector<Viewpoint> views;
  for (double x : {-8.0, 8.0, 0.0}) {  // left slope, right slope, then overhead
    Viewpoint v;
    v.eye = Vec3(x, 5, x == 0 ? 20 : 8);
    v.target = Vec3(x / 2, 5, 2.5);
    v.up = x == 0 ? Vec3::UnitY() : Vec3::UnitZ();
    v.fov_y_deg = 90;
    views.push_back(v);
  }
  ConstrainedMesh cpu = noisy_gable();
  OptimizeReport rc = optimize_views(cpu, views, opts(ComputeDevice::Cpu));
  ASSERT_EQ(rc.view_tasks.size(), 3u);
  EXPECT_GT(rc.view_tasks[0], 0);
  for (std::size_t i = 1; i < rc.energy.size(); ++i) EXPECT_LE(rc.energy[i], rc.energy[i - 1]);
  EXPECT_LT(rc.energy.back(), 0.05 * rc.energy.front());
  // A vertex refined by an earlier view is not dispatched again.
  EXPECT_LT(rc.view_tasks[2], rc.view_tasks[0] + rc.view_tasks[1]);
  C3D_NEED(have_vulkan(), "no Vulkan device");
  ConstrainedMesh gpu = noisy_gable();
  OptimizeReport rg = optimize_views(gpu, views, opts(ComputeDevice::Vulkan));
  EXPECT_EQ(rc.view_tasks, rg.view_tasks);
  expect_same_vertices(cpu, gpu);
}

TEST(Optimizer, CurvatureSubdivision) {
  ConstrainedMesh cm = noisy_gable(0.03, 0.5);
  const std::size_t before = cm.mesh.triangles.size();
  OptimizerOptions o = opts(ComputeDevice::Cpu);
  o.subdivide = true;
  o.curvature_threshold_deg = 2.0;
  OptimizeReport r = optimize_mesh(cm, o);
  EXPECT_GT(r.triangles_subdivided, 0);
  EXPECT_GT(cm.mesh.triangles.size(), before);
  EXPECT_LT(r.max_plane_distance, 1e-4);
  EXPECT_LT(r.max_line_distance, 1e-3);
}

TEST(Optimizer, BuildingJunctionsAndPlanarity) {
  // Two roof faces whose shared ridge vertices are off by a few cm; points on the true planes.
  Building b;
  Element left, right;
  Face fl, fr;
  fl.ring = {Vec3(-5, 0, 0.02), Vec3(0, 0, 2.5), Vec3(0.03, 8, 2.46), Vec3(-5, 8, -0.01)};
  fr.ring = {Vec3(0, 0, 2.5), Vec3(5, 0, 0.01), Vec3(5, 8, 0.03), Vec3(0.03, 8, 2.46)};
  left.faces = {fl};
  right.faces = {fr};
  b.elements = {left, right};
  std::vector<Vec3> pts;
  for (double x = -4.8; x < 4.8; x += 0.2)
    for (double y = 0.2; y < 7.8; y += 0.2) pts.push_back(Vec3(x, y, 2.5 - 0.5 * std::fabs(x)));
  OptimizeReport r = optimize_building(b, pts, opts(ComputeDevice::Auto));
  EXPECT_GT(r.junction_vertices, 0);
  EXPECT_LT(r.max_line_distance, 1e-3);
  for (const Element& e : b.elements)
    for (const Vec3& p : e.faces[0].ring) EXPECT_NEAR(p.z(), 2.5 - 0.5 * std::fabs(p.x()), 2e-3);
  EXPECT_NEAR(b.elements[0].faces[0].ring[2].x(), 0.0, 2e-3);  // ridge vertex moved onto the ridge
}

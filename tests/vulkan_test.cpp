// Vulkan runner and the grid point-to-mesh distance (GPU vs CPU vs brute force).
#include <gtest/gtest.h>

#include <random>

#include "core/optimizer/mesh_distance.h"
#include "core/optimizer/vulkan_compute.h"
#include "tests/test_support.h"

using namespace c3d;

namespace {
std::vector<Triangle3> random_surface(int n, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(0, 20), s(-0.5, 0.5);
  std::vector<Triangle3> t;
  for (int i = 0; i < n; ++i) {
    Vec3 c(u(rng), u(rng), 0.2 * u(rng));
    t.push_back({c, c + Vec3(s(rng), s(rng), s(rng)), c + Vec3(s(rng), s(rng), s(rng))});
  }
  return t;
}

double brute(const Vec3& p, const std::vector<Triangle3>& tris) {
  double best = 1e300;
  for (const auto& t : tris) {  // dense barycentric sampling is too slow; use projection + edges
    Vec3 a = t[0], b = t[1], c = t[2], n = (b - a).cross(c - a);
    double best_t = 1e300;
    if (n.norm() > 1e-12) {
      n.normalize();
      Vec3 q = p - n.dot(p - a) * n;
      Vec3 ca = (b - a).cross(q - a), cb = (c - b).cross(q - b), cc = (a - c).cross(q - c);
      if (ca.dot(n) >= 0 && cb.dot(n) >= 0 && cc.dot(n) >= 0) best_t = (p - q).norm();
    }
    for (auto [e0, e1] : {std::pair<Vec3, Vec3>{a, b}, {b, c}, {c, a}}) {
      Vec3 e = e1 - e0;
      double s = std::clamp((p - e0).dot(e) / std::max(e.squaredNorm(), 1e-30), 0.0, 1.0);
      best_t = std::min(best_t, (p - (e0 + s * e)).norm());
    }
    best = std::min(best, best_t);
  }
  return best;
}
}  // namespace

TEST(Vulkan, DeviceParsingAndCpuChoice) {
  EXPECT_EQ(parse_compute_device("cpu"), ComputeDevice::Cpu);
  EXPECT_EQ(parse_compute_device("auto"), ComputeDevice::Auto);
  EXPECT_THROW(parse_compute_device("gpu0"), std::exception);
  std::string note;
  EXPECT_EQ(select_compute(ComputeDevice::Cpu, &note), nullptr);
  EXPECT_NE(note.find("CPU"), std::string::npos);
}

TEST(Vulkan, DeviceAvailableUnderCtest) {
  std::string why;
  VulkanCompute* vk = shared_vulkan(&why);
  C3D_NEED(vk, "no Vulkan: " << why);
  EXPECT_FALSE(vk->device_name().empty());
  std::string note;
  EXPECT_EQ(select_compute(ComputeDevice::Auto, &note), vk);
  EXPECT_NE(note.find(vk->device_name()), std::string::npos);
}

TEST(PointToMesh, GridMatchesBruteForceOnCpu) {
  std::mt19937 rng(3);
  auto tris = random_surface(300, rng);
  std::uniform_real_distribution<double> u(-3, 23);
  std::vector<Vec3> pts;
  for (int i = 0; i < 500; ++i) pts.push_back(Vec3(u(rng), u(rng), u(rng) * 0.3));
  auto d = point_to_mesh_distances(pts, tris, ComputeDevice::Cpu);
  for (std::size_t i = 0; i < pts.size(); ++i) EXPECT_NEAR(d[i], brute(pts[i], tris), 1e-5);
}

TEST(PointToMesh, VulkanMatchesCpu) {
  C3D_NEED(shared_vulkan(), "no Vulkan device");
  std::mt19937 rng(5);
  auto tris = random_surface(5000, rng);
  std::uniform_real_distribution<double> u(-2, 22);
  std::vector<Vec3> pts;
  for (int i = 0; i < 100000; ++i) pts.push_back(Vec3(u(rng), u(rng), u(rng) * 0.3));
  std::string used;
  DistanceOptions o;
  o.device = ComputeDevice::Vulkan;
  o.used = &used;
  auto g = point_to_mesh_distances(pts, tris, o);
  EXPECT_NE(used.find("Vulkan"), std::string::npos);
  auto c = point_to_mesh_distances(pts, tris, ComputeDevice::Cpu);
  double worst = 0;
  for (std::size_t i = 0; i < pts.size(); ++i) worst = std::max(worst, std::fabs(g[i] - c[i]));
  EXPECT_LT(worst, 1e-5);
}

TEST(PointToMesh, ChamferOfIdenticalMeshesIsZero) {
  std::mt19937 rng(9);
  auto tris = random_surface(200, rng);
  EXPECT_LT(chamfer_distance(tris, tris, {ComputeDevice::Cpu}), 1e-6);
}

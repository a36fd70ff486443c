// Benchmark (not a test): optimizer and point-to-mesh distance on
// 1 M points / 100 k triangles; CPU 1 thread, CPU all cores, Vulkan.
// Usage: bench_optimizer [points=1000000] [grid=224 -> 2*224^2 = 100352 triangles]
//                        [columns=cpu1,cpuN,vulkan: which of the three to run]
// Vulkan picks a discrete GPU when present, else lavapipe (set VK_DRIVER_FILES to force one).
#include <chrono>
#include <cstdio>
#include <random>
#include <string>
#include <thread>
#include <tuple>
#include <utility>

#include "core/optimizer/mesh_distance.h"
#include "core/optimizer/optimizer.h"
#include "core/optimizer/optimizer_kernels.h"
#include "core/optimizer/vulkan_compute.h"

using namespace c3d;

namespace {

double now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// Noisy gable roof, n x n cells over 40 m x 40 m.
ConstrainedMesh roof(int n) {
  ConstrainedMesh cm;
  std::mt19937 rng(1);
  std::normal_distribution<double> g(0, 0.03);
  const double step = 40.0 / n, ridge = 0.07;
  auto z = [&](double x) { return 8 - 0.5 * std::fabs(x - ridge); };
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      double x = -20 + i * step;
      cm.mesh.vertices.push_back(Vec3(x + g(rng), j * step + g(rng), z(x) + g(rng)));
    }
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      int a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
      double cx = -20 + (i + 0.5) * step;
      cm.mesh.triangles.push_back({a, b, d});
      cm.mesh.triangles.push_back({a, d, c});
      cm.tri_plane.push_back(cx < ridge ? 0 : 1);
      cm.tri_plane.push_back(cx < ridge ? 0 : 1);
    }
  Vec3 nl = Vec3(-0.5, 0, 1).normalized(), nr = Vec3(0.5, 0, 1).normalized();
  cm.planes = {PrimitivePlane{nl, -nl.dot(Vec3(ridge, 0, 8))}, PrimitivePlane{nr, -nr.dot(Vec3(ridge, 0, 8))}};
  cm.lines = {intersect_planes(cm.planes[0], cm.planes[1], 0, 1)};
  return cm;
}

struct Row {
  std::string name;
  double t[3] = {-1, -1, -1};
};

void print(const std::vector<Row>& rows, int threads, const std::string& vk_name) {
  std::printf("\n%-44s %14s %14s %14s\n", "task (seconds, lower is better)", "CPU 1 thread",
              ("CPU " + std::to_string(threads) + " thr").c_str(), "Vulkan");
  for (const Row& r : rows) {
    std::printf("%-44s", r.name.c_str());
    for (double t : r.t) t < 0 ? std::printf(" %14s", "n/a") : std::printf(" %14.3f", t);
    std::printf("\n");
  }
  std::printf("\nVulkan device: %s\n", vk_name.c_str());
}

// Kernel-only timings on a prepared state (upload + dispatch + read-back for
// Vulkan): seconds for 10 energy and 10 refine passes.
std::pair<double, double> time_kernels(const ConstrainedMesh& base, VulkanCompute* k, int thr) {
  KernelState s;
  s.v.resize(3 * base.mesh.vertices.size());
  for (std::size_t i = 0; i < base.mesh.vertices.size(); ++i)
    for (int c = 0; c < 3; ++c) s.v[3 * i + c] = static_cast<float>(base.mesh.vertices[i][c]);
  s.vplane.assign(base.mesh.vertices.size(), 0);
  s.vline.assign(base.mesh.vertices.size(), 0);
  s.weight.assign(base.mesh.vertices.size(), 1.0f);
  s.planes = {0.f, 0.f, 1.f, -8.f};
  s.lines = {0.f, 0.f, 8.f, 0.f, 0.f, 1.f, 0.f, 0.f};
  std::vector<float> terms;
  kernel_energy(s, terms, k, thr);  // warm-up (pipeline creation)
  double t0 = now();
  for (int i = 0; i < 10; ++i) kernel_energy(s, terms, k, thr);
  const double energy = now() - t0;
  std::vector<std::uint32_t> tasks(base.mesh.vertices.size());
  for (std::size_t i = 0; i < tasks.size(); ++i) tasks[i] = static_cast<std::uint32_t>(i);
  kernel_refine(s, tasks, 1000, k, thr);
  t0 = now();
  for (int i = 0; i < 10; ++i) kernel_refine(s, tasks, 1000, k, thr);
  return {energy, now() - t0};
}

// Points scattered within 0.3 m of the roof.
std::vector<Vec3> roof_points(std::size_t npoints) {
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> ux(-20, 20), uy(0, 40), uz(-0.3, 0.3);
  std::vector<Vec3> pts(npoints);
  for (auto& p : pts) {
    double x = ux(rng);
    p = Vec3(x, uy(rng), 8 - 0.5 * std::fabs(x - 0.07) + uz(rng));
  }
  return pts;
}

}  // namespace

int main(int argc, char** argv) {
  const std::size_t npoints = argc > 1 ? std::stoul(argv[1]) : 1000000;
  const int grid = argc > 2 ? std::stoi(argv[2]) : 224;
  const int threads = resolve_threads(0);
  const std::string columns = argc > 3 ? argv[3] : "cpu1,cpuN,vulkan";
  const char* column_names[3] = {"cpu1", "cpuN", "vulkan"};
  std::string why;
  VulkanCompute* vk = shared_vulkan(&why);
  const std::string vk_name = vk ? vk->device_name() + " (" + vk->device_type() + ")" : "none: " + why;

  const ConstrainedMesh base = roof(grid);
  const auto tris = base.mesh.soup();
  const std::vector<Vec3> pts = roof_points(npoints);
  std::printf("mesh: %zu triangles, %zu vertices; points: %zu; CPU threads: %d\n", tris.size(),
              base.mesh.vertices.size(), pts.size(), threads);

  std::vector<Row> rows(4);
  rows[0].name = "point-to-mesh distance (grid)";
  rows[1].name = "optimize_mesh end to end";
  rows[2].name = "energy kernel (x10)";
  rows[3].name = "refine kernel (x10)";
  std::vector<double> ref;
  double worst = 0;
  for (int col = 0; col < 3; ++col) {
    if (col == 2 && !vk) break;
    if (columns.find(column_names[col]) == std::string::npos) continue;
    const int thr = col == 0 ? 1 : threads;
    const ComputeDevice dev = col == 2 ? ComputeDevice::Vulkan : ComputeDevice::Cpu;
    VulkanCompute* k = col == 2 ? vk : nullptr;

    DistanceOptions d;
    d.device = dev;
    d.threads = thr;
    double t0 = now();
    auto dist = point_to_mesh_distances(pts, tris, d);
    rows[0].t[col] = now() - t0;
    const bool first_column = ref.empty();
    if (first_column) ref = dist;
    for (std::size_t i = 0; i < dist.size(); ++i) worst = std::max(worst, std::fabs(dist[i] - ref[i]));

    ConstrainedMesh cm = base;
    OptimizerOptions o;
    o.device = dev;
    o.threads = thr;
    t0 = now();
    OptimizeReport r = optimize_mesh(cm, o);
    rows[1].t[col] = now() - t0;
    if (first_column)
      std::printf("optimizer: energy %.4g -> %.4g, junction max %.2e m, %d clusters\n", r.energy.front(),
                  r.energy.back(), r.max_line_distance, r.clusters);

    std::tie(rows[2].t[col], rows[3].t[col]) = time_kernels(base, k, thr);
  }
  print(rows, threads, vk_name);
  std::printf("max |distance difference| vs the first column run: %.2e m\n", worst);
  return 0;
}

#pragma once
// The optimizer's per-element kernels, each with a CPU reference (float, the
// same arithmetic as the GLSL in shaders/opt_*.comp) and a Vulkan path.
// Pass vk == nullptr for the CPU reference; threads <= 0 means all cores.
#include <cstdint>
#include <functional>
#include <vector>

namespace c3d {

class VulkanCompute;

// Float state of a constrained mesh in local coordinates, laid out as the
// shaders read it.
struct KernelState {
  std::vector<float> v;          // 3 per vertex
  std::vector<std::uint32_t> tri;  // 3 per triangle
  std::vector<std::int32_t> vplane;  // per vertex: plane index or -1
  std::vector<std::int32_t> vline;   // per vertex: intersection line or -1 (junction vertex)
  std::vector<std::int32_t> tplane;  // per triangle: plane index or -1
  std::vector<float> weight;     // per vertex fitness weight
  std::vector<float> planes;     // 4 per plane: unit normal, d (n.p + d = 0)
  std::vector<float> lines;      // 8 per line: point, 0, unit direction, 0
  std::size_t vertex_count() const { return v.size() / 3; }
  std::size_t triangle_count() const { return tri.size() / 3; }
};

// Splits [0, n) into contiguous chunks over `threads` std::threads.
void parallel_for(std::size_t n, int threads, const std::function<void(std::size_t, std::size_t)>& body);
int resolve_threads(int threads);

// terms[2i] = w_i * dist(v_i, plane)^2, terms[2i+1] = dist(v_i, line)^2.
void kernel_energy(const KernelState& s, std::vector<float>& terms, VulkanCompute* vk,
                   int threads = 1);
// v_i = R_c v_i + t_c for c = vcluster[i] >= 0; xf holds 12 floats per cluster
// (R row-major, then t).
void kernel_transform(KernelState& s, const std::vector<std::int32_t>& vcluster,
                      const std::vector<float>& xf, VulkanCompute* vk, int threads = 1);
// For each task t (a distinct vertex index): t < n_junction snaps the vertex onto
// its line, later tasks project it onto its plane.
void kernel_refine(KernelState& s, const std::vector<std::uint32_t>& tasks,
                   std::uint32_t n_junction, VulkanCompute* vk, int threads = 1);
// v_i snapped onto curved surface vsurface[i] >= 0 along its normal; surfaces
// holds 12 floats each, heights the height fields' knots and poles, laid out
// as shaders/opt_snap_curved.comp reads them.
void kernel_snap_curved(std::vector<float>& v, const std::vector<std::int32_t>& vsurface,
                        const std::vector<float>& surfaces, const std::vector<float>& heights, VulkanCompute* vk,
                        int threads = 1);
// flags[t] = 1 when triangle t's centroid is inside the frustum of view_proj
// (column-major, clip |x|,|y|,|z| <= w), it faces eye, and a vertex lies farther
// than threshold from its plane.
void kernel_view_select(const KernelState& s, const float view_proj[16], const float eye[3],
                        float threshold, std::vector<std::uint32_t>& flags, VulkanCompute* vk,
                        int threads = 1);

}  // namespace c3d

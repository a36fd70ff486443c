// CPU references and Vulkan dispatch of the optimizer kernels. The CPU code
// mirrors the GLSL operation by operation (float) so that both paths agree to
// float rounding.
#include "core/optimizer/optimizer_kernels.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <thread>

#include "core/optimizer/height_field_eval.h"
#include "core/optimizer/vulkan_compute.h"

namespace c3d {
namespace {

struct F3 {
  float x, y, z;
};
inline F3 load(const std::vector<float>& a, std::size_t i) { return {a[3 * i], a[3 * i + 1], a[3 * i + 2]}; }
inline void store(std::vector<float>& a, std::size_t i, F3 p) {
  a[3 * i] = p.x;
  a[3 * i + 1] = p.y;
  a[3 * i + 2] = p.z;
}
inline F3 sub(F3 a, F3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline F3 add(F3 a, F3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline F3 mul(F3 a, float s) { return {a.x * s, a.y * s, a.z * s}; }
inline float dot(F3 a, F3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline F3 cross(F3 a, F3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
inline F3 plane_n(const KernelState& s, int k) { return {s.planes[4 * k], s.planes[4 * k + 1], s.planes[4 * k + 2]}; }
inline float plane_d(const KernelState& s, int k) { return s.planes[4 * k + 3]; }
inline F3 line_o(const KernelState& s, int l) { return {s.lines[8 * l], s.lines[8 * l + 1], s.lines[8 * l + 2]}; }
inline F3 line_dir(const KernelState& s, int l) { return {s.lines[8 * l + 4], s.lines[8 * l + 5], s.lines[8 * l + 6]}; }

template <class T>
GpuBuffer in(const std::vector<T>& a) {
  return {const_cast<T*>(a.data()), a.size() * sizeof(T), false};
}
template <class T>
GpuBuffer inout(std::vector<T>& a) {
  return {a.data(), a.size() * sizeof(T), true};
}

}  // namespace

int resolve_threads(int threads) {
  if (threads > 0) return threads;
  unsigned hw = std::thread::hardware_concurrency();
  return hw ? static_cast<int>(hw) : 1;
}

void parallel_for(std::size_t n, int threads, const std::function<void(std::size_t, std::size_t)>& body) {
  const std::size_t t = std::min<std::size_t>(static_cast<std::size_t>(resolve_threads(threads)),
                                              std::max<std::size_t>(n / 1024, 1));
  if (t <= 1) {
    body(0, n);
    return;
  }
  std::vector<std::thread> pool;
  const std::size_t chunk = (n + t - 1) / t;
  for (std::size_t b = 0; b < n; b += chunk) pool.emplace_back(body, b, std::min(n, b + chunk));
  for (auto& th : pool) th.join();
}

void kernel_energy(const KernelState& s, std::vector<float>& terms, VulkanCompute* vk, int threads) {
  const std::size_t n = s.vertex_count();
  terms.assign(2 * n, 0.0f);
  if (vk) {
    std::uint32_t push = static_cast<std::uint32_t>(n);
    vk->run("opt_energy", {in(s.v), in(s.vplane), in(s.vline), in(s.planes), in(s.lines), in(s.weight), inout(terms)},
            &push, sizeof push, n);
    return;
  }
  parallel_for(n, threads, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) {
      F3 p = load(s.v, i);
      float fit = 0.0f, junc = 0.0f;
      if (int k = s.vplane[i]; k >= 0) {
        float d = dot(plane_n(s, k), p) + plane_d(s, k);
        fit = s.weight[i] * d * d;
      }
      if (int l = s.vline[i]; l >= 0) {
        F3 q = sub(p, line_o(s, l));
        F3 dir = line_dir(s, l);
        F3 r = sub(q, mul(dir, dot(q, dir)));
        junc = dot(r, r);
      }
      terms[2 * i] = fit;
      terms[2 * i + 1] = junc;
    }
  });
}

void kernel_transform(KernelState& s, const std::vector<std::int32_t>& vcluster,
                      const std::vector<float>& xf, VulkanCompute* vk, int threads) {
  const std::size_t n = s.vertex_count();
  if (vk) {
    std::uint32_t push = static_cast<std::uint32_t>(n);
    vk->run("opt_transform", {inout(s.v), in(vcluster), in(xf)}, &push, sizeof push, n);
    return;
  }
  parallel_for(n, threads, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) {
      int c = vcluster[i];
      if (c < 0) continue;
      const float* m = &xf[12 * static_cast<std::size_t>(c)];
      F3 p = load(s.v, i);
      store(s.v, i, {m[0] * p.x + m[1] * p.y + m[2] * p.z + m[9],
                     m[3] * p.x + m[4] * p.y + m[5] * p.z + m[10],
                     m[6] * p.x + m[7] * p.y + m[8] * p.z + m[11]});
    }
  });
}

void kernel_refine(KernelState& s, const std::vector<std::uint32_t>& tasks, std::uint32_t n_junction,
                   VulkanCompute* vk, int threads) {
  if (vk) {
    std::uint32_t push[2] = {static_cast<std::uint32_t>(tasks.size()), n_junction};
    vk->run("opt_refine", {inout(s.v), in(tasks), in(s.vplane), in(s.vline), in(s.planes), in(s.lines)},
            push, sizeof push, tasks.size());
    return;
  }
  parallel_for(tasks.size(), threads, [&](std::size_t b, std::size_t e) {
    for (std::size_t t = b; t < e; ++t) {
      const std::uint32_t i = tasks[t];
      F3 p = load(s.v, i);
      if (t < n_junction) {
        int l = s.vline[i];
        if (l < 0) continue;
        F3 o = line_o(s, l), dir = line_dir(s, l);
        p = add(o, mul(dir, dot(sub(p, o), dir)));
      } else {
        int k = s.vplane[i];
        if (k < 0) continue;
        F3 n = plane_n(s, k);
        p = sub(p, mul(n, dot(n, p) + plane_d(s, k)));
      }
      store(s.v, i, p);
    }
  });
}

namespace {

// The point of height field f (12 floats, its knots and poles in heights)
// nearest p.
F3 onto_height_field(F3 p, const float* f, const std::vector<float>& heights) {
  const int nu = int(f[8]), nv = int(f[9]);
  const float* ku = &heights[std::size_t(f[6])];
  const float *kv = ku + nu + 4, *z = kv + nv + 4;
  const float dx = p.x - f[0], dy = p.y - f[1], e1x = f[4], e1y = f[5];
  const float pu = dx * e1x + dy * e1y, pv = dy * e1x - dx * e1y;
  float u = 0, w = 0;
  nearest_parameters(ku, nu, kv, nv, z, pu, pv, p.z, u, w);
  const float h = height_at(ku, nu, kv, nv, z, u, w).h;
  return {f[0] + u * e1x - w * e1y, f[1] + u * e1y + w * e1x, h};
}

}  // namespace

void kernel_snap_curved(std::vector<float>& v, const std::vector<std::int32_t>& vsurface,
                        const std::vector<float>& surfaces, const std::vector<float>& heights, VulkanCompute* vk,
                        int threads) {
  if (vk) {
    std::uint32_t push[1] = {static_cast<std::uint32_t>(vsurface.size())};
    vk->run("opt_snap_curved", {inout(v), in(vsurface), in(surfaces), in(heights)}, push, sizeof push,
            vsurface.size());
    return;
  }
  parallel_for(vsurface.size(), threads, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) {
      const int k = vsurface[i];
      if (k < 0) continue;
      const float* f = &surfaces[12 * std::size_t(k)];
      const F3 c{f[0], f[1], f[2]}, a{f[4], f[5], f[6]}, q = sub(load(v, i), c);
      const float kind = f[3], r = f[7];
      F3 p;
      if (kind == 4.0f) {
        p = onto_height_field(load(v, i), f, heights);
      } else if (kind == 3.0f) {
        p = sub(load(v, i), mul(a, dot(q, a)));
      } else if (kind == 0.0f) {
        const float len = std::sqrt(dot(q, q));
        if (len <= 0.0f) continue;
        p = add(c, mul(q, r / len));
      } else {
        const float t = dot(q, a);
        const F3 radial = sub(q, mul(a, t));
        const float rho = std::sqrt(dot(radial, radial));
        if (rho <= 0.0f) continue;
        const F3 e_dir = mul(radial, 1.0f / rho);
        if (kind == 1.0f) {
          p = add(add(c, mul(a, t)), mul(e_dir, r));
        } else {
          const F3 g = add(mul(a, f[8]), mul(e_dir, f[9]));  // the generator through the vertex
          p = add(c, mul(g, std::max(dot(q, g), 0.0f)));
        }
      }
      store(v, i, p);
    }
  });
}

void kernel_view_select(const KernelState& s, const float view_proj[16], const float eye[3],
                        float threshold, std::vector<std::uint32_t>& flags, VulkanCompute* vk,
                        int threads) {
  const std::size_t n = s.triangle_count();
  flags.assign(n, 0u);
  if (vk) {
    struct Push {
      float vp[16];
      float eye[4];
      std::uint32_t n;
      float threshold;
    } push{};
    std::memcpy(push.vp, view_proj, sizeof push.vp);
    std::memcpy(push.eye, eye, 3 * sizeof(float));
    push.n = static_cast<std::uint32_t>(n);
    push.threshold = threshold;
    vk->run("opt_view_select", {in(s.v), in(s.tri), in(s.tplane), in(s.planes), inout(flags)}, &push,
            sizeof push, n);
    return;
  }
  const F3 e{eye[0], eye[1], eye[2]};
  const float* m = view_proj;
  parallel_for(n, threads, [&](std::size_t b, std::size_t end) {
    for (std::size_t i = b; i < end; ++i) {
      int k = s.tplane[i];
      if (k < 0) continue;
      F3 a = load(s.v, s.tri[3 * i]), bb = load(s.v, s.tri[3 * i + 1]), c = load(s.v, s.tri[3 * i + 2]);
      F3 mid = mul(add(add(a, bb), c), 1.0f / 3.0f);
      float cx = m[0] * mid.x + m[4] * mid.y + m[8] * mid.z + m[12];
      float cy = m[1] * mid.x + m[5] * mid.y + m[9] * mid.z + m[13];
      float cz = m[2] * mid.x + m[6] * mid.y + m[10] * mid.z + m[14];
      float cw = m[3] * mid.x + m[7] * mid.y + m[11] * mid.z + m[15];
      bool inside = cw > 0 && std::fabs(cx) <= cw && std::fabs(cy) <= cw && std::fabs(cz) <= cw;
      bool front = dot(cross(sub(bb, a), sub(c, a)), sub(e, mid)) > 0.0f;
      F3 pn = plane_n(s, k);
      float pd = plane_d(s, k);
      float dev = std::max(std::fabs(dot(pn, a) + pd),
                           std::max(std::fabs(dot(pn, bb) + pd), std::fabs(dot(pn, c) + pd)));
      if (inside && front && dev > threshold) flags[i] = 1u;
    }
  });
}

}  // namespace c3d

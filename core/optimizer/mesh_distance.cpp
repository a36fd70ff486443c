// Uniform-grid point-to-triangle distance: grid built on the CPU (CSR lists of
// triangles per cell), query ring by ring on the GPU or in the CPU reference.
#include "core/optimizer/mesh_distance.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "core/optimizer/optimizer_kernels.h"

namespace c3d {
namespace {

struct Grid {
  float origin[3] = {0, 0, 0};
  float h = 1;
  int n[3] = {1, 1, 1};
  std::vector<float> tv;                 // 9 floats per triangle
  std::vector<std::uint32_t> cell_start;  // n cells + 1
  std::vector<std::uint32_t> cell_tris;
};

// Cell size about twice the mean edge, enlarged until the grid has <= 4 M cells.
Grid build_grid(const std::vector<Triangle3>& tris) {
  Grid g;
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
  double edge = 0;
  g.tv.reserve(tris.size() * 9);
  for (const auto& t : tris) {
    for (const auto& p : t) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
      for (int k = 0; k < 3; ++k) g.tv.push_back(static_cast<float>(p[k]));
    }
    edge += (t[1] - t[0]).norm() + (t[2] - t[1]).norm() + (t[0] - t[2]).norm();
  }
  if (tris.empty()) lo = hi = Eigen::Vector3d::Zero();
  double h = std::max(2.0 * edge / std::max<std::size_t>(3 * tris.size(), 1), 1e-3);
  Eigen::Vector3d ext = (hi - lo).cwiseMax(1e-6);
  auto cells = [&](double s) { return (ext / s).array().floor().matrix() + Eigen::Vector3d::Ones(); };
  while (cells(h).prod() > 4e6) h *= 1.25;
  g.h = static_cast<float>(h);
  for (int k = 0; k < 3; ++k) {
    g.origin[k] = static_cast<float>(lo[k]);
    g.n[k] = static_cast<int>(cells(h)[k]);
  }
  const std::size_t ncell = static_cast<std::size_t>(g.n[0]) * g.n[1] * g.n[2];
  // Each triangle goes into every cell its bounding box touches.
  auto cell_range = [&](const Triangle3& t, int a[3], int b[3]) {
    for (int k = 0; k < 3; ++k) {
      double mn = std::min({t[0][k], t[1][k], t[2][k]}), mx = std::max({t[0][k], t[1][k], t[2][k]});
      a[k] = std::clamp(static_cast<int>(std::floor((mn - g.origin[k]) / h)), 0, g.n[k] - 1);
      b[k] = std::clamp(static_cast<int>(std::floor((mx - g.origin[k]) / h)), 0, g.n[k] - 1);
    }
  };
  std::vector<std::uint32_t> count(ncell + 1, 0);
  for (int pass = 0; pass < 2; ++pass) {
    if (pass == 1) {
      g.cell_start.assign(ncell + 1, 0);
      for (std::size_t c = 0; c < ncell; ++c) g.cell_start[c + 1] = g.cell_start[c] + count[c];
      g.cell_tris.resize(g.cell_start[ncell]);
      std::copy(g.cell_start.begin(), g.cell_start.end() - 1, count.begin());
    }
    for (std::size_t i = 0; i < tris.size(); ++i) {
      int a[3], b[3];
      cell_range(tris[i], a, b);
      for (int z = a[2]; z <= b[2]; ++z)
        for (int y = a[1]; y <= b[1]; ++y)
          for (int x = a[0]; x <= b[0]; ++x) {
            std::size_t c = (static_cast<std::size_t>(z) * g.n[1] + y) * g.n[0] + x;
            if (pass == 0) ++count[c];
            else g.cell_tris[count[c]++] = static_cast<std::uint32_t>(i);
          }
    }
  }
  return g;
}

struct F3 {
  float x, y, z;
};
inline F3 sub(F3 a, F3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline F3 add(F3 a, F3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline F3 mul(F3 a, float s) { return {a.x * s, a.y * s, a.z * s}; }
inline float dot(F3 a, F3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

// Same branch structure as tri_dist2 in shaders/point_distance.comp.
float tri_dist2(F3 p, F3 a, F3 b, F3 c) {
  F3 ab = sub(b, a), ac = sub(c, a), ap = sub(p, a), q;
  float d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) {
    q = a;
  } else {
    F3 bp = sub(p, b);
    float d3 = dot(ab, bp), d4 = dot(ac, bp);
    float vc = d1 * d4 - d3 * d2;
    if (d3 >= 0 && d4 <= d3) {
      q = b;
    } else if (vc <= 0 && d1 >= 0 && d3 <= 0) {
      q = add(a, mul(ab, d1 / (d1 - d3)));
    } else {
      F3 cp = sub(p, c);
      float d5 = dot(ab, cp), d6 = dot(ac, cp);
      float vb = d5 * d2 - d1 * d6;
      float va = d3 * d6 - d5 * d4;
      if (d6 >= 0 && d5 <= d6) {
        q = c;
      } else if (vb <= 0 && d2 >= 0 && d6 <= 0) {
        q = add(a, mul(ac, d2 / (d2 - d6)));
      } else if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
        q = add(b, mul(sub(c, b), (d4 - d3) / ((d4 - d3) + (d5 - d6))));
      } else {
        float denom = 1.0f / (va + vb + vc);
        q = add(add(a, mul(ab, vb * denom)), mul(ac, vc * denom));
      }
    }
  }
  F3 r = sub(p, q);
  return dot(r, r);
}

float query(const Grid& g, F3 p, float cap) {
  const int* n = g.n;
  int c[3];
  const float pv[3] = {p.x, p.y, p.z};
  for (int k = 0; k < 3; ++k)
    c[k] = std::clamp(static_cast<int>(std::floor((pv[k] - g.origin[k]) / g.h)), 0, n[k] - 1);
  int max_r = std::max({n[0], n[1], n[2]});
  if (cap < 1.0e30f) max_r = std::min(max_r, static_cast<int>(std::ceil(cap / g.h)) + 1);
  float best = 3.0e38f;
  auto tv = [&](std::uint32_t t, int k) {
    const float* f = &g.tv[9 * static_cast<std::size_t>(t) + 3 * k];
    return F3{f[0], f[1], f[2]};
  };
  for (int r = 0; r <= max_r; ++r) {
    int lo[3], hi[3];
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::max(c[k] - r, 0);
      hi[k] = std::min(c[k] + r, n[k] - 1);
    }
    for (int z = lo[2]; z <= hi[2]; ++z)
      for (int y = lo[1]; y <= hi[1]; ++y)
        for (int x = lo[0]; x <= hi[0]; ++x) {
          if (std::max({std::abs(x - c[0]), std::abs(y - c[1]), std::abs(z - c[2])}) != r) continue;
          std::size_t cell = (static_cast<std::size_t>(z) * n[1] + y) * n[0] + x;
          for (std::uint32_t k = g.cell_start[cell]; k < g.cell_start[cell + 1]; ++k) {
            std::uint32_t t = g.cell_tris[k];
            best = std::min(best, tri_dist2(p, tv(t, 0), tv(t, 1), tv(t, 2)));
          }
        }
    float reach = static_cast<float>(r) * g.h;
    if (best <= reach * reach) break;
  }
  return best > cap * cap ? std::numeric_limits<float>::infinity() : std::sqrt(best);
}

}  // namespace

std::vector<double> point_to_mesh_distances(const std::vector<Vec3>& points,
                                            const std::vector<Triangle3>& triangles,
                                            ComputeDevice device) {
  DistanceOptions o;
  o.device = device;
  return point_to_mesh_distances(points, triangles, o);
}

std::vector<double> point_to_mesh_distances(const std::vector<Vec3>& points,
                                            const std::vector<Triangle3>& triangles,
                                            const DistanceOptions& options) {
  std::vector<double> out(points.size(), std::numeric_limits<double>::infinity());
  if (triangles.empty() || points.empty()) return out;
  const Grid g = build_grid(triangles);
  std::vector<float> pts(3 * points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
    for (int k = 0; k < 3; ++k) pts[3 * i + k] = static_cast<float>(points[i][k]);
  std::vector<float> dist(points.size(), 0.0f);
  const float cap = std::isfinite(options.beyond_m) ? static_cast<float>(options.beyond_m) : 3.0e38f;
  std::string note;
  VulkanCompute* vk = select_compute(options.device, &note);
  if (options.used) *options.used = note;
  if (vk) {
    struct Push {
      float ox, oy, oz, h;
      std::int32_t nx, ny, nz;
      std::uint32_t np;
      float cap;
    } push{g.origin[0], g.origin[1], g.origin[2], g.h, g.n[0], g.n[1], g.n[2],
           static_cast<std::uint32_t>(points.size()), cap};
    vk->run("point_distance",
            {{pts.data(), pts.size() * 4, false},
             {const_cast<float*>(g.tv.data()), g.tv.size() * 4, false},
             {const_cast<std::uint32_t*>(g.cell_start.data()), g.cell_start.size() * 4, false},
             {const_cast<std::uint32_t*>(g.cell_tris.data()), g.cell_tris.size() * 4, false},
             {dist.data(), dist.size() * 4, true}},
            &push, sizeof push, points.size());
  } else {
    parallel_for(points.size(), options.threads, [&](std::size_t b, std::size_t e) {
      for (std::size_t i = b; i < e; ++i)
        dist[i] = query(g, F3{pts[3 * i], pts[3 * i + 1], pts[3 * i + 2]}, cap);
    });
  }
  for (std::size_t i = 0; i < points.size(); ++i) out[i] = dist[i];
  return out;
}

namespace {
std::vector<Vec3> samples(const std::vector<Triangle3>& tris) {
  std::vector<Vec3> s;
  s.reserve(tris.size() * 4);
  for (const auto& t : tris) {
    s.push_back(t[0]);
    s.push_back(t[1]);
    s.push_back(t[2]);
    s.push_back((t[0] + t[1] + t[2]) / 3.0);
  }
  return s;
}
double mean(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return v.empty() ? 0 : s / static_cast<double>(v.size());
}
}  // namespace

double chamfer_distance(const std::vector<Triangle3>& a, const std::vector<Triangle3>& b,
                        const DistanceOptions& options) {
  return 0.5 * (mean(point_to_mesh_distances(samples(a), b, options)) +
                mean(point_to_mesh_distances(samples(b), a, options)));
}

}  // namespace c3d

// Primitive-constrained optimizer: topology work (subdivision, splitting along
// intersection lines, clustering) and the small Kabsch solves on the CPU, the
// per-vertex work through core/optimizer_kernels (Vulkan or CPU reference).
#include "core/optimizer/optimizer.h"

#include <Eigen/Dense>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <numeric>
#include <queue>
#include <unordered_map>

#include "core/optimizer/mesh_subdivision.h"
#include "core/optimizer/optimizer_kernels.h"

namespace c3d {
namespace {

constexpr double kPi = 3.14159265358979323846;
using Tri = std::array<int, 3>;

std::uint64_t edge_key(int a, int b) {
  if (a > b) std::swap(a, b);
  return (static_cast<std::uint64_t>(a) << 32) | static_cast<std::uint32_t>(b);
}

Vec3 tri_normal(const TriMesh& m, const Tri& t) {
  Vec3 n = (m.vertices[t[1]] - m.vertices[t[0]]).cross(m.vertices[t[2]] - m.vertices[t[0]]);
  double l = n.norm();
  return l > 0 ? Vec3(n / l) : Vec3::Zero();
}

Vec3 centroid(const TriMesh& m, const Tri& t) {
  return (m.vertices[t[0]] + m.vertices[t[1]] + m.vertices[t[2]]) / 3.0;
}

// Splits triangle v by its cut edges m[k] (edge v[k]-v[k+1], -1 = not cut),
// keeping the orientation; appends the pieces with the given label.
void emit_split(const Tri& v, const std::array<int, 3>& m, std::vector<Tri>& out) {
  int cuts = (m[0] >= 0) + (m[1] >= 0) + (m[2] >= 0);
  if (cuts == 0) {
    out.push_back(v);
  } else if (cuts == 3) {
    out.push_back({v[0], m[0], m[2]});
    out.push_back({m[0], v[1], m[1]});
    out.push_back({m[2], m[1], v[2]});
    out.push_back({m[0], m[1], m[2]});
  } else {
    int r = 0;  // rotate: 1 cut -> edge r is cut; 2 cuts -> edges r and r+1 are cut
    for (int k = 0; k < 3; ++k) {
      bool a = m[k] >= 0, b = m[(k + 1) % 3] >= 0;
      if ((cuts == 1 && a) || (cuts == 2 && a && b)) r = k;
    }
    int a = v[r], b = v[(r + 1) % 3], c = v[(r + 2) % 3], mab = m[r], mbc = m[(r + 1) % 3];
    if (cuts == 1) {
      out.push_back({a, mab, c});
      out.push_back({mab, b, c});
    } else {
      out.push_back({a, mab, mbc});
      out.push_back({mab, b, mbc});
      out.push_back({a, mbc, c});
    }
  }
}

// Replaces every triangle by its pieces; labels are copied from the parent.
int apply_cuts(TriMesh& mesh, std::vector<int>& labels, const std::unordered_map<std::uint64_t, int>& cut) {
  std::vector<Tri> tris;
  std::vector<int> pieces_labels;
  int split = 0;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Tri& v = mesh.triangles[t];
    std::array<int, 3> m{};
    for (int k = 0; k < 3; ++k) {
      auto it = cut.find(edge_key(v[k], v[(k + 1) % 3]));
      m[k] = it == cut.end() ? -1 : it->second;
    }
    std::size_t before = tris.size();
    emit_split(v, m, tris);
    if (tris.size() - before > 1) ++split;
    pieces_labels.resize(tris.size(), labels[t]);
  }
  mesh.triangles = std::move(tris);
  labels = std::move(pieces_labels);
  return split;
}

}  // namespace

int subdivide_marked(TriMesh& mesh, std::vector<int>& labels, const std::vector<char>& marked) {
  std::unordered_map<std::uint64_t, int> mid;
  int count = 0;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    if (!marked[t]) continue;
    ++count;
    const Tri& v = mesh.triangles[t];
    for (int k = 0; k < 3; ++k) {
      int a = v[k], b = v[(k + 1) % 3];
      if (mid.emplace(edge_key(a, b), static_cast<int>(mesh.vertices.size())).second)
        mesh.vertices.push_back(0.5 * (mesh.vertices[a] + mesh.vertices[b]));
    }
  }
  apply_cuts(mesh, labels, mid);
  return count;
}

namespace {

// Surface junction optimization: triangles whose normal departs from their
// plane's by more than the threshold get one midpoint level, three when over
// 10x. Midpoint children keep the parent's normal, so each round re-measures.
int subdivide_by_curvature(ConstrainedMesh& cm, double threshold_rad) {
  int total = 0;
  for (int round = 1; round <= 3; ++round) {
    const double limit = round == 1 ? threshold_rad : 10 * threshold_rad;
    std::vector<char> marked(cm.mesh.triangles.size(), 0);
    bool any = false;
    for (std::size_t t = 0; t < marked.size(); ++t) {
      if (cm.tri_plane[t] < 0) continue;
      double c = tri_normal(cm.mesh, cm.mesh.triangles[t]).dot(cm.planes[cm.tri_plane[t]].n);
      any |= marked[t] = std::acos(std::clamp(std::fabs(c), 0.0, 1.0)) > limit;
    }
    if (!any) break;
    total += subdivide_marked(cm.mesh, cm.tri_plane, marked);
  }
  return total;
}

// Linear junction optimization for one line: the separator plane through the
// line bisects the two planes; band triangles crossing it are split along it,
// those on plane A's side align to A (M1), the rest to B (M2).
int split_along_line(ConstrainedMesh& cm, int li, double band, std::vector<int>& on_line) {
  const PrimitiveLine& L = cm.lines[li];
  const int a = L.plane_a, b = L.plane_b;
  Vec3 sep = cm.planes[a].n - cm.planes[b].n;
  if (sep.norm() < 1e-6) return 0;
  sep.normalize();
  auto side = [&](const Vec3& p) { return sep.dot(p - L.point); };
  auto in_band = [&](const Vec3& p) { return L.distance(p) <= band; };
  // Orient the separator from the data: plane A's band triangles on the + side.
  double vote = 0;
  for (std::size_t t = 0; t < cm.mesh.triangles.size(); ++t) {
    Vec3 c = centroid(cm.mesh, cm.mesh.triangles[t]);
    if (!in_band(c)) continue;
    if (cm.tri_plane[t] == a) vote += side(c);
    if (cm.tri_plane[t] == b) vote -= side(c);
  }
  if (vote < 0) sep = -sep;
  const double eps = 1e-7;
  auto sgn = [&](int v) {
    double s = side(cm.mesh.vertices[v]);
    return std::fabs(s) < eps ? 0 : (s > 0 ? 1 : -1);
  };
  // Edges to cut: endpoints on opposite sides, crossing in the band, and every
  // triangle using the edge belongs to A or B.
  std::unordered_map<std::uint64_t, int> users_ok;  // +1 per A/B user, -1000 otherwise
  for (std::size_t t = 0; t < cm.mesh.triangles.size(); ++t) {
    const Tri& v = cm.mesh.triangles[t];
    bool ab = cm.tri_plane[t] == a || cm.tri_plane[t] == b;
    for (int k = 0; k < 3; ++k) users_ok[edge_key(v[k], v[(k + 1) % 3])] += ab ? 1 : -1000;
  }
  std::unordered_map<std::uint64_t, int> cut;
  for (const auto& [key, ok] : users_ok) {
    if (ok <= 0) continue;
    int i = static_cast<int>(key >> 32), j = static_cast<int>(key & 0xffffffffu);
    if (sgn(i) * sgn(j) >= 0) continue;
    const Vec3 &pi = cm.mesh.vertices[i], &pj = cm.mesh.vertices[j];
    double si = side(pi), sj = side(pj);
    Vec3 x = pi + (pj - pi) * (si / (si - sj));
    if (!in_band(x)) continue;
    cut[key] = static_cast<int>(cm.mesh.vertices.size());
    cm.mesh.vertices.push_back(x);
  }
  int split = apply_cuts(cm.mesh, cm.tri_plane, cut);
  on_line.resize(cm.mesh.vertices.size(), -1);
  for (std::size_t v = 0; v < cm.mesh.vertices.size(); ++v)
    if (sgn(static_cast<int>(v)) == 0 && in_band(cm.mesh.vertices[v])) on_line[v] = li;
  for (std::size_t t = 0; t < cm.mesh.triangles.size(); ++t) {
    int& lab = cm.tri_plane[t];
    Vec3 c = centroid(cm.mesh, cm.mesh.triangles[t]);
    if ((lab == a || lab == b) && in_band(c)) lab = side(c) > 0 ? a : b;
  }
  return split;
}

// Float kernel state; vertex planes by majority of incident triangles, junction
// vertices from on_line or from touching both planes of a line.
KernelState make_state(const ConstrainedMesh& cm, const std::vector<int>& on_line) {
  KernelState s;
  const std::size_t nv = cm.mesh.vertices.size();
  s.v.resize(3 * nv);
  for (std::size_t i = 0; i < nv; ++i)
    for (int k = 0; k < 3; ++k) s.v[3 * i + k] = static_cast<float>(cm.mesh.vertices[i][k]);
  for (const Tri& t : cm.mesh.triangles)
    for (int k : t) s.tri.push_back(static_cast<std::uint32_t>(k));
  s.tplane.assign(cm.tri_plane.begin(), cm.tri_plane.end());
  for (const PrimitivePlane& p : cm.planes)
    for (double x : {p.n.x(), p.n.y(), p.n.z(), p.d}) s.planes.push_back(static_cast<float>(x));
  for (const PrimitiveLine& l : cm.lines)
    for (double x : {l.point.x(), l.point.y(), l.point.z(), 0.0, l.dir.x(), l.dir.y(), l.dir.z(), 0.0})
      s.lines.push_back(static_cast<float>(x));
  s.weight.assign(nv, 1.0f);
  for (std::size_t i = 0; i < cm.vertex_weight.size() && i < nv; ++i)
    s.weight[i] = static_cast<float>(cm.vertex_weight[i]);

  std::vector<std::map<int, int>> votes(nv);
  for (std::size_t t = 0; t < cm.mesh.triangles.size(); ++t)
    if (cm.tri_plane[t] >= 0)
      for (int k : cm.mesh.triangles[t]) ++votes[k][cm.tri_plane[t]];
  std::map<std::pair<int, int>, int> line_of;
  for (std::size_t l = 0; l < cm.lines.size(); ++l) {
    int a = cm.lines[l].plane_a, b = cm.lines[l].plane_b;
    line_of[{std::min(a, b), std::max(a, b)}] = static_cast<int>(l);
  }
  s.vplane.assign(nv, -1);
  s.vline.assign(nv, -1);
  for (std::size_t i = 0; i < nv; ++i) {
    int best = 0;
    for (auto [p, c] : votes[i])
      if (c > best) best = c, s.vplane[i] = p;
    if (i < on_line.size() && on_line[i] >= 0) {
      s.vline[i] = on_line[i];
      continue;
    }
    for (auto [p, c] : votes[i])
      for (auto [q, d] : votes[i]) {
        auto it = line_of.find({p, q});
        if (p < q && it != line_of.end()) s.vline[i] = it->second;
      }
  }
  return s;
}

void write_back(ConstrainedMesh& cm, const KernelState& s) {
  for (std::size_t i = 0; i < cm.mesh.vertices.size(); ++i)
    cm.mesh.vertices[i] = Vec3(s.v[3 * i], s.v[3 * i + 1], s.v[3 * i + 2]);
}

double energy(const KernelState& s, const OptimizerOptions& o, VulkanCompute* vk) {
  std::vector<float> terms;
  kernel_energy(s, terms, vk, o.threads);
  double fit = 0, junc = 0;
  for (std::size_t i = 0; i < terms.size(); i += 2) fit += terms[i], junc += terms[i + 1];
  return o.alpha * fit + o.beta * junc;
}

// Region growing over edge-adjacent triangles of one plane whose normals stay
// within epsilon of the seed's.
std::vector<int> cluster_triangles(const ConstrainedMesh& cm, double eps_rad, int* count) {
  const auto& tris = cm.mesh.triangles;
  std::unordered_map<std::uint64_t, std::vector<int>> by_edge;
  for (std::size_t t = 0; t < tris.size(); ++t)
    for (int k = 0; k < 3; ++k) by_edge[edge_key(tris[t][k], tris[t][(k + 1) % 3])].push_back(static_cast<int>(t));
  std::vector<int> cl(tris.size(), -1);
  const double cos_eps = std::cos(eps_rad);
  int next = 0;
  for (std::size_t seed = 0; seed < tris.size(); ++seed) {
    if (cl[seed] >= 0 || cm.tri_plane[seed] < 0) continue;
    const Vec3 n0 = tri_normal(cm.mesh, tris[seed]);
    std::queue<int> q;
    q.push(static_cast<int>(seed));
    cl[seed] = next;
    while (!q.empty()) {
      int t = q.front();
      q.pop();
      for (int k = 0; k < 3; ++k)
        for (int u : by_edge[edge_key(tris[t][k], tris[t][(k + 1) % 3])]) {
          if (cl[u] >= 0 || cm.tri_plane[u] != cm.tri_plane[seed]) continue;
          if (tri_normal(cm.mesh, tris[u]).dot(n0) < cos_eps) continue;
          cl[u] = next;
          q.push(u);
        }
    }
    ++next;
  }
  *count = next;
  return cl;
}

// Least-squares rigid transform src -> dst (Kabsch), as 12 floats (R row-major, t).
std::array<float, 12> kabsch(const std::vector<Vec3>& src, const std::vector<Vec3>& dst) {
  Vec3 cs = Vec3::Zero(), cd = Vec3::Zero();
  for (std::size_t i = 0; i < src.size(); ++i) cs += src[i], cd += dst[i];
  cs /= static_cast<double>(src.size());
  cd /= static_cast<double>(src.size());
  Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
  for (std::size_t i = 0; i < src.size(); ++i) H += (src[i] - cs) * (dst[i] - cd).transpose();
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  if (src.size() >= 3) {
    Eigen::JacobiSVD<Eigen::Matrix3d> svd(H, Eigen::ComputeFullU | Eigen::ComputeFullV);
    Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
    D(2, 2) = (svd.matrixV() * svd.matrixU().transpose()).determinant() < 0 ? -1 : 1;
    R = svd.matrixV() * D * svd.matrixU().transpose();
  }
  Vec3 t = cd - R * cs;
  std::array<float, 12> out{};
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) out[3 * r + c] = static_cast<float>(R(r, c));
  for (int k = 0; k < 3; ++k) out[9 + k] = static_cast<float>(t[k]);
  return out;
}

// Surface optimization: one rigid transform per normal cluster, fitted to
// sampled (non-junction) vertices and their projections on the cluster's plane.
int cluster_transform(const ConstrainedMesh& cm, KernelState& s, const OptimizerOptions& o,
                      VulkanCompute* vk) {
  int nclusters = 0;
  std::vector<int> tcl = cluster_triangles(cm, o.cluster_angle_deg * kPi / 180, &nclusters);
  std::vector<std::int32_t> vcl(s.vertex_count(), -1);
  std::vector<int> cl_plane(nclusters, -1);
  std::vector<std::vector<int>> members(nclusters);
  for (std::size_t t = 0; t < tcl.size(); ++t) {
    if (tcl[t] < 0) continue;
    cl_plane[tcl[t]] = cm.tri_plane[t];
    for (int v : cm.mesh.triangles[t])
      if (vcl[v] < 0 && s.vline[v] < 0 && s.vplane[v] == cm.tri_plane[t]) {
        vcl[v] = tcl[t];
        members[tcl[t]].push_back(v);
      }
  }
  std::vector<float> xf(12 * std::max(nclusters, 1), 0.0f);
  for (int c = 0; c < nclusters; ++c) {
    const auto& mv = members[c];
    std::array<float, 12> m{1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0};
    if (!mv.empty()) {
      const PrimitivePlane& pl = cm.planes[cl_plane[c]];
      std::vector<Vec3> src, dst;
      std::size_t stride = std::max<std::size_t>(1, mv.size() / std::max(o.cluster_samples, 1));
      for (std::size_t k = 0; k < mv.size(); k += stride) {
        Vec3 p(s.v[3 * mv[k]], s.v[3 * mv[k] + 1], s.v[3 * mv[k] + 2]);
        src.push_back(p);
        dst.push_back(p - pl.distance(p) * pl.n);
      }
      m = kabsch(src, dst);
    }
    std::copy(m.begin(), m.end(), xf.begin() + 12 * c);
  }
  kernel_transform(s, vcl, xf, vk, o.threads);
  return nclusters;
}

// Task list for the refine kernel: junction vertices first, then plane vertices.
std::vector<std::uint32_t> refine_tasks(const KernelState& s, const std::vector<char>* only,
                                        std::uint32_t* n_junction) {
  std::vector<std::uint32_t> tasks;
  for (std::size_t i = 0; i < s.vertex_count(); ++i)
    if (s.vline[i] >= 0 && (!only || (*only)[i])) tasks.push_back(static_cast<std::uint32_t>(i));
  *n_junction = static_cast<std::uint32_t>(tasks.size());
  for (std::size_t i = 0; i < s.vertex_count(); ++i)
    if (s.vline[i] < 0 && s.vplane[i] >= 0 && (!only || (*only)[i]))
      tasks.push_back(static_cast<std::uint32_t>(i));
  return tasks;
}

void finish_report(OptimizeReport& r, const ConstrainedMesh& cm, const KernelState& s) {
  r.max_plane_distance = r.max_line_distance = 0;
  r.junction_vertices = 0;
  for (std::size_t i = 0; i < s.vertex_count(); ++i) {
    const Vec3& p = cm.mesh.vertices[i];
    if (s.vplane[i] >= 0)
      r.max_plane_distance = std::max(r.max_plane_distance, std::fabs(cm.planes[s.vplane[i]].distance(p)));
    if (s.vline[i] >= 0) {
      ++r.junction_vertices;
      r.max_line_distance = std::max(r.max_line_distance, cm.lines[s.vline[i]].distance(p));
    }
  }
}

// Subdivision and junction splitting; returns the on-line marks per vertex.
std::vector<int> prepare(ConstrainedMesh& cm, const OptimizerOptions& o, OptimizeReport& r) {
  if (cm.tri_plane.size() != cm.mesh.triangles.size()) cm.tri_plane.resize(cm.mesh.triangles.size(), -1);
  if (o.subdivide)
    r.triangles_subdivided = subdivide_by_curvature(cm, o.curvature_threshold_deg * kPi / 180);
  std::vector<int> on_line(cm.mesh.vertices.size(), -1);
  if (o.split_junctions)
    for (std::size_t l = 0; l < cm.lines.size(); ++l)
      r.triangles_split += split_along_line(cm, static_cast<int>(l), o.junction_band_m, on_line);
  cm.vertex_weight.resize(std::min(cm.vertex_weight.size(), cm.mesh.vertices.size()));
  if (!cm.vertex_weight.empty()) cm.vertex_weight.resize(cm.mesh.vertices.size(), 1.0);
  return on_line;
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Column-major perspective * look-at (OpenGL clip conventions).
std::array<float, 16> view_projection(const Viewpoint& v) {
  Vec3 f = (v.target - v.eye).normalized(), s = f.cross(v.up).normalized(), u = s.cross(f);
  Eigen::Matrix4d view = Eigen::Matrix4d::Identity();
  view.block<1, 3>(0, 0) = s.transpose();
  view.block<1, 3>(1, 0) = u.transpose();
  view.block<1, 3>(2, 0) = -f.transpose();
  view(0, 3) = -s.dot(v.eye);
  view(1, 3) = -u.dot(v.eye);
  view(2, 3) = f.dot(v.eye);
  double t = 1.0 / std::tan(v.fov_y_deg * kPi / 360), n = v.near_m, fa = v.far_m;
  Eigen::Matrix4d proj = Eigen::Matrix4d::Zero();
  proj(0, 0) = t / v.aspect;
  proj(1, 1) = t;
  proj(2, 2) = -(fa + n) / (fa - n);
  proj(2, 3) = -2 * fa * n / (fa - n);
  proj(3, 2) = -1;
  Eigen::Matrix4d vp = proj * view;
  std::array<float, 16> out{};
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) out[4 * c + r] = static_cast<float>(vp(r, c));
  return out;
}

}  // namespace

PrimitiveLine intersect_planes(const PrimitivePlane& a, const PrimitivePlane& b, int ia, int ib) {
  PrimitiveLine l;
  l.dir = a.n.cross(b.n).normalized();
  // Point on both planes closest to the origin: solve [na; nb; dir] p = [-da; -db; 0].
  Eigen::Matrix3d A;
  A.row(0) = a.n.transpose();
  A.row(1) = b.n.transpose();
  A.row(2) = l.dir.transpose();
  l.point = A.colPivHouseholderQr().solve(Vec3(-a.d, -b.d, 0));
  l.plane_a = ia;
  l.plane_b = ib;
  return l;
}

std::vector<PrimitiveLine> adjacent_plane_lines(const ConstrainedMesh& m) {
  std::unordered_map<std::uint64_t, std::vector<int>> by_edge;
  for (std::size_t t = 0; t < m.mesh.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k)
      by_edge[edge_key(m.mesh.triangles[t][k], m.mesh.triangles[t][(k + 1) % 3])].push_back(m.tri_plane[t]);
  std::map<std::pair<int, int>, int> pairs;
  for (const auto& [e, labels] : by_edge)
    for (int a : labels)
      for (int b : labels)
        if (a >= 0 && b >= 0 && a < b) ++pairs[{a, b}];
  std::vector<PrimitiveLine> lines;
  for (const auto& [p, n] : pairs) {
    const PrimitivePlane &a = m.planes[p.first], &b = m.planes[p.second];
    if (a.n.cross(b.n).norm() < std::sin(5 * kPi / 180)) continue;
    lines.push_back(intersect_planes(a, b, p.first, p.second));
  }
  return lines;
}

double mesh_energy(const ConstrainedMesh& m, const OptimizerOptions& options) {
  OptimizerOptions o = options;
  return energy(make_state(m, {}), o, nullptr);
}

OptimizeReport optimize_mesh(ConstrainedMesh& cm, const OptimizerOptions& o) {
  const auto t0 = std::chrono::steady_clock::now();
  OptimizeReport r;
  VulkanCompute* vk = select_compute(o.device, &r.device);
  std::vector<int> on_line = prepare(cm, o, r);
  KernelState s = make_state(cm, on_line);
  r.energy.push_back(energy(s, o, vk));
  r.clusters = cluster_transform(cm, s, o, vk);
  r.energy.push_back(energy(s, o, vk));
  std::uint32_t nj = 0;
  std::vector<std::uint32_t> tasks = refine_tasks(s, nullptr, &nj);
  kernel_refine(s, tasks, nj, vk, o.threads);
  r.energy.push_back(energy(s, o, vk));
  write_back(cm, s);
  finish_report(r, cm, s);
  r.seconds = seconds_since(t0);
  return r;
}

OptimizeReport optimize_views(ConstrainedMesh& cm, const std::vector<Viewpoint>& views,
                              const OptimizerOptions& o) {
  const auto t0 = std::chrono::steady_clock::now();
  OptimizeReport r;
  VulkanCompute* vk = select_compute(o.device, &r.device);
  std::vector<int> on_line = prepare(cm, o, r);
  KernelState s = make_state(cm, on_line);
  r.energy.push_back(energy(s, o, vk));
  for (const Viewpoint& view : views) {
    std::array<float, 16> vp = view_projection(view);
    const float eye[3] = {static_cast<float>(view.eye.x()), static_cast<float>(view.eye.y()),
                          static_cast<float>(view.eye.z())};
    std::vector<std::uint32_t> flags;
    kernel_view_select(s, vp.data(), eye, static_cast<float>(o.view_threshold_m), flags, vk, o.threads);
    std::vector<char> active(s.vertex_count(), 0);
    for (std::size_t t = 0; t < flags.size(); ++t)
      if (flags[t])
        for (int k = 0; k < 3; ++k) active[s.tri[3 * t + k]] = 1;
    std::uint32_t nj = 0;
    std::vector<std::uint32_t> tasks = refine_tasks(s, &active, &nj);
    kernel_refine(s, tasks, nj, vk, o.threads);
    r.view_tasks.push_back(static_cast<int>(tasks.size()));
    r.energy.push_back(energy(s, o, vk));
  }
  write_back(cm, s);
  finish_report(r, cm, s);
  r.seconds = seconds_since(t0);
  return r;
}

}  // namespace c3d

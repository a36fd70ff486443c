#include "core/reconstruct/envelope/shell.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>
#include <utility>

#include "core/geometry/geometry.h"
#include "core/log.h"
#include "core/reconstruct/envelope/common.h"

namespace c3d::envelope {

// A shell face the weld left with less area than this is a line, no face.
constexpr double kMinShellFaceArea = 1e-6;  // m^2
// debug_open_edges matches edge ends on keys of this many per metre (0.1 mm).
constexpr double kOpenEdgeKeys = 1e4;

namespace {

void set_height(Face& f, double z) {
  for (auto& v : f.ring) v.z() = z;
  for (auto& h : f.holes)
    for (auto& v : h) v.z() = z;
}

}  // namespace

// Vertices closer than tol become one (the first seen), and rings lose the
// consecutive duplicates that leaves: validators treat < 1 mm as the same point.
void weld_faces(std::vector<Face>& shell, Welder<Vec3>& welder, bool drop_degenerate) {
  auto clean = [&](Ring3& r) {
    for (auto& v : r) welder.weld(v);
    Ring3 out;
    for (const auto& v : r)
      if (out.empty() || (v - out.back()).norm() > 0) out.push_back(v);
    while (out.size() > 1 && out.front() == out.back()) out.pop_back();
    r = out;
  };
  for (auto& f : shell) {
    clean(f.ring);
    for (auto& h : f.holes) clean(h);
  }
  if (drop_degenerate)
    shell.erase(std::remove_if(shell.begin(), shell.end(),
                               [](const Face& f) { return f.ring.size() < 3 || area(f) < kMinShellFaceArea; }),
                shell.end());
}

std::vector<Vec3> shell_vertices(const std::vector<Face>& shell) {
  std::vector<Vec3> verts;
  for (const auto& f : shell) {
    verts.insert(verts.end(), f.ring.begin(), f.ring.end());
    for (const auto& h : f.holes) verts.insert(verts.end(), h.begin(), h.end());
  }
  return verts;
}

// Inserts into every shell edge the shell vertices lying on it (a wall corner
// that meets a step between roof levels, a T-junction left by clipping), so each
// edge is shared by exactly two faces.
void node_faces(std::vector<Face>& shell, const EdgeNoder<Vec3>& noder) {
  for (auto& f : shell) {
    f.ring = noder.insert_on_edges(f.ring);
    for (auto& h : f.holes) h = noder.insert_on_edges(h);
  }
}

void weld_shell(std::vector<Face>& solid, std::vector<Element>& elements) {
  // Weld and node the shell, then the element faces against the same vertices,
  // so an element face and its copy in the shell stay identical.
  Welder<Vec3> pool(kWeldTol);
  weld_faces(solid, pool, true);
  const std::vector<Vec3> verts = shell_vertices(solid);
  const EdgeNoder<Vec3> noder(verts, kWeldTol);
  node_faces(solid, noder);
  for (auto& e : elements) {
    std::vector<double> level;  // an outer ceiling is horizontal: welding must not tilt it
    for (const auto& f : e.faces) level.push_back(f.ring.empty() ? 0.0 : f.ring[0].z());
    weld_faces(e.faces, pool, false);
    node_faces(e.faces, noder);
    if (e.type == ElementType::OuterCeiling)
      for (size_t i = 0; i < e.faces.size(); ++i) set_height(e.faces[i], level[i]);
    // A face the weld left a line (a step wall's sliver whose ends met) has
    // no area; the shell has dropped its copy, and no polygon can hold it.
    e.faces.erase(std::remove_if(e.faces.begin(), e.faces.end(), [](const Face& f) { return f.ring.size() < 3; }),
                  e.faces.end());
  }
  elements.erase(std::remove_if(elements.begin(), elements.end(), [](const Element& e) { return e.faces.empty(); }),
                 elements.end());
}

// Developer aid: logs the shell edges not used by exactly two faces (debug level).
void debug_open_edges(const Building& b) {
  auto key = [](const Vec3& p) {
    return std::make_tuple(std::llround(p.x() * kOpenEdgeKeys), std::llround(p.y() * kOpenEdgeKeys),
                           std::llround(p.z() * kOpenEdgeKeys));
  };
  std::map<std::pair<decltype(key(Vec3())), decltype(key(Vec3()))>, int> use;
  auto count = [&](const Ring3& r) {
    for (size_t i = 0; i < r.size(); ++i) {
      auto a = key(r[i]), c = key(r[(i + 1) % r.size()]);
      use[{std::min(a, c), std::max(a, c)}]++;
    }
  };
  for (const auto& f : b.solid) {
    count(f.ring);
    for (const auto& h : f.holes) count(h);
  }
  for (auto& [e, n] : use)
    if (n != 2)
      log::debug(log::format("%s open edge x%d (%.3f %.3f %.3f)-(%.3f %.3f %.3f)", b.id.c_str(), n,
                             std::get<0>(e.first) / kOpenEdgeKeys, std::get<1>(e.first) / kOpenEdgeKeys,
                             std::get<2>(e.first) / kOpenEdgeKeys, std::get<0>(e.second) / kOpenEdgeKeys,
                             std::get<1>(e.second) / kOpenEdgeKeys, std::get<2>(e.second) / kOpenEdgeKeys));
}

}  // namespace c3d::envelope

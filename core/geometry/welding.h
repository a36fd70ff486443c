#pragma once
// Making faces that share boundaries share vertices (2D rings of the roof
// partition, 3D rings of the shell), one algorithm for both. Vertices are
// found through a hash of cells, so a building of thousands of vertices does
// not compare each with all (the answers are those of the plain scans: the
// first vertex in order, the vertices of an edge in the order given).
#include <algorithm>
#include <cmath>
#include <unordered_map>
#include <utility>
#include <vector>

#include "core/geometry/cell_key.h"
#include "core/types.h"

namespace c3d {
// Snaps each vertex to the first vertex kept before it closer than tol, else
// keeps it: validators treat points this close as one.
template <class V>
class Welder {
  static constexpr int D = V::RowsAtCompileTime;

 public:
  // Cells of 2 tol: a kept vertex within tol lies in the cells round the
  // vertex's own, float rounding of the cell index included.
  explicit Welder(double tol) : tol_(tol), cell_(std::max(2 * tol, 1e-9)) {}

  void weld(V& v) {
    int first = -1;
    for_cells_round<D>(cell_key<D>(v, cell_), [&](const auto& k) {
      const auto it = cells_.find(k);
      if (it == cells_.end()) return;
      for (int s : it->second)
        if ((first < 0 || s < first) && (seen_[size_t(s)] - v).norm() < tol_) first = s;
    });
    if (first >= 0) {
      v = seen_[size_t(first)];
      return;
    }
    cells_[cell_key<D>(v, cell_)].push_back(int(seen_.size()));
    seen_.push_back(v);
  }
  const std::vector<V>& seen() const { return seen_; }

 private:
  double tol_, cell_;
  std::vector<V> seen_;
  std::unordered_map<CellKey<D>, std::vector<int>, CellKeyHash<D>> cells_;
};

// Puts into each edge of a ring, in order, the vertices of `verts` lying on it
// within tol (T-junctions), away from its ends. The vertices are indexed by
// plan cells; an edge reads the cells along it.
template <class V>
class EdgeNoder {
 public:
  static constexpr double kCellM = 1.0;

  EdgeNoder(const std::vector<V>& verts, double tol) : verts_(verts), tol_(tol) {
    for (size_t i = 0; i < verts.size(); ++i) cells_[plan_cell(verts[i].x(), verts[i].y())].push_back(int(i));
  }

  std::vector<V> insert_on_edges(const std::vector<V>& ring) const {
    std::vector<V> out;
    for (size_t i = 0; i < ring.size(); ++i) {
      const V a = ring[i], b = ring[(i + 1) % ring.size()];
      out.push_back(a);
      const V ab = b - a;
      const double len2 = ab.squaredNorm();
      if (len2 < tol_ * tol_) continue;
      std::vector<std::pair<double, V>> inner;
      // A vertex within tol of the edge lies in its box grown by tol (2 tol: rounding).
      const V lo = a.cwiseMin(b).array() - 2 * tol_, hi = a.cwiseMax(b).array() + 2 * tol_;
      for (int k : near_edge(a, b)) {
        const V& v = verts_[size_t(k)];
        if ((v.array() < lo.array()).any() || (v.array() > hi.array()).any()) continue;
        const double t = (v - a).dot(ab) / len2;
        if (t <= 1e-9 || t >= 1 - 1e-9) continue;
        if ((a + t * ab - v).norm() < tol_ && (v - a).norm() > tol_ && (v - b).norm() > tol_) inner.emplace_back(t, v);
      }
      std::sort(inner.begin(), inner.end(), [](auto& x, auto& y) { return x.first < y.first; });
      for (auto& [t, v] : inner)
        if ((v - out.back()).norm() > tol_) out.push_back(v);
    }
    return out;
  }

 private:
  using Key = CellKey<2>;

  static Key plan_cell(double x, double y) { return cell_key<2>(Vec2(x, y), kCellM); }

  // The indices, ascending, of the vertices in the cells within 2 tol of the
  // edge ab in plan, a cell's length of it at a time.
  std::vector<int> near_edge(const V& a, const V& b) const {
    std::vector<int> found;
    const Vec2 pa(a.x(), a.y()), pb(b.x(), b.y());
    const int pieces = 1 + int(std::ceil((pb - pa).norm() / kCellM));
    for (int p = 0; p < pieces; ++p) {
      const Vec2 from = pa + (pb - pa) * (double(p) / pieces), to = pa + (pb - pa) * (double(p + 1) / pieces);
      const Key lo = plan_cell(std::min(from.x(), to.x()) - 2 * tol_, std::min(from.y(), to.y()) - 2 * tol_);
      const Key hi = plan_cell(std::max(from.x(), to.x()) + 2 * tol_, std::max(from.y(), to.y()) + 2 * tol_);
      for (int64_t cx = lo[0]; cx <= hi[0]; ++cx)
        for (int64_t cy = lo[1]; cy <= hi[1]; ++cy) {
          const auto it = cells_.find(Key{cx, cy});
          if (it != cells_.end()) found.insert(found.end(), it->second.begin(), it->second.end());
        }
    }
    std::sort(found.begin(), found.end());
    found.erase(std::unique(found.begin(), found.end()), found.end());
    return found;
  }

  const std::vector<V>& verts_;
  double tol_;
  std::unordered_map<Key, std::vector<int>, CellKeyHash<2>> cells_;
};

}  // namespace c3d

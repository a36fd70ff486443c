#include "core/reconstruct/lod13/layers.h"

#include <algorithm>
#include <cmath>
#include <deque>

#include "core/geometry/geometry.h"
#include "core/reconstruct/lod13/raster.h"

namespace c3d::lod13 {
namespace {

// Thresholds tried when splitting a layer: these quantiles of its own cells'
// heights (a finer sweep moves the split by centimetres only).
constexpr int kThresholdQuantiles = 20;
// A split must explain at least this share of the layer's height spread
// (sum of squares): less is a sloped or noisy roof better left in one layer.
constexpr double kMinExplainedShare = 0.2;
// Empty cells are filled from their neighbours at most this many rounds; a
// footprint still empty after that (no points near) takes the median height.
constexpr int kFillRounds = 50;

struct Stats {
  double n = 0, sum = 0, sum2 = 0;
  void add(double v) { n += 1, sum += v, sum2 += v * v; }
  double mean() const { return n > 0 ? sum / n : 0; }
  double sse() const { return n > 0 ? sum2 - sum * sum / n : 0; }
};

Stats stats_of(const HeightGrid& g, const std::vector<int>& cells) {
  Stats s;
  for (int c : cells) s.add(g.z[size_t(c)]);
  return s;
}

double median_height(const HeightGrid& g, const std::vector<int>& cells) {
  std::vector<double> z;
  for (int c : cells) z.push_back(g.z[size_t(c)]);
  if (z.empty()) return kNaN;
  std::nth_element(z.begin(), z.begin() + long(z.size() / 2), z.end());
  return z[z.size() / 2];
}

// Each neighbour-less cell takes the mean of its neighbours' heights, round
// by round, so holes in the points close from their rims.
void fill_empty(HeightGrid& g, std::vector<bool> known) {
  for (int round = 0; round < kFillRounds; ++round) {
    std::vector<std::pair<int, double>> filled;
    for (int i = 0; i < g.nx * g.ny; ++i) {
      if (known[size_t(i)] || !g.on_footprint(i)) continue;
      double sum = 0;
      int n = 0;
      for (int j : neighbours8(g.nx, g.ny, i))
        if (known[size_t(j)]) sum += g.z[size_t(j)], ++n;
      if (n > 0) filled.push_back({i, sum / n});
    }
    if (filled.empty()) break;
    for (auto [i, z] : filled) g.z[size_t(i)] = z, known[size_t(i)] = true;
  }
  std::vector<int> have;
  for (int i = 0; i < g.nx * g.ny; ++i)
    if (known[size_t(i)]) have.push_back(i);
  const double fallback = median_height(g, have);
  for (int i = 0; i < g.nx * g.ny; ++i)
    if (g.on_footprint(i) && !known[size_t(i)]) g.z[size_t(i)] = fallback;
}

// The patches of `cells` at or above `t` (4-connected), those of at least
// `min_cells` cells.
std::vector<std::vector<int>> patches_above(const HeightGrid& g, const std::vector<int>& cells, double t,
                                            size_t min_cells) {
  std::vector<int> above;
  for (int c : cells)
    if (g.z[size_t(c)] >= t) above.push_back(c);
  std::vector<std::vector<int>> out;
  for (auto& p : connected_patches(g.nx, g.ny, above))
    if (p.size() >= min_cells) out.push_back(std::move(p));
  return out;
}

struct Split {
  std::vector<std::vector<int>> children;
  double explained = 0;  // sum of squares the split explains
};

// The threshold split of a layer's own cells that explains most of their
// spread, its children each at least min_step above what stays.
Split best_split(const HeightGrid& g, const std::vector<int>& own, const LayerOptions& o) {
  const size_t min_cells = size_t(std::ceil(o.min_area_m2 / (g.cell * g.cell)));
  const Stats all = stats_of(g, own);
  Split best;
  if (own.size() < 2 * min_cells || all.sse() <= all.n * o.tolerance_m * o.tolerance_m) return best;
  std::vector<double> z;
  for (int c : own) z.push_back(g.z[size_t(c)]);
  std::sort(z.begin(), z.end());
  for (int q = 1; q < kThresholdQuantiles; ++q) {
    const double t = z[z.size() * size_t(q) / kThresholdQuantiles];
    if (t <= z.front()) continue;
    Split s;
    std::vector<bool> taken(g.z.size(), false);
    double sse = 0;
    for (auto& p : patches_above(g, own, t, min_cells)) {
      for (int c : p) taken[size_t(c)] = true;
      sse += stats_of(g, p).sse();
      s.children.push_back(std::move(p));
    }
    std::vector<int> rest;
    for (int c : own)
      if (!taken[size_t(c)]) rest.push_back(c);
    if (s.children.empty() || rest.size() < min_cells) continue;
    const Stats stay = stats_of(g, rest);
    bool steps = true;
    for (const auto& p : s.children) steps = steps && stats_of(g, p).mean() - stay.mean() >= o.min_step_m;
    s.explained = all.sse() - sse - stay.sse();
    if (steps && s.explained > best.explained) best = std::move(s);
  }
  if (best.explained < kMinExplainedShare * all.sse()) best.children.clear();
  return best;
}

std::vector<int> own_cells(const std::vector<int>& owner, const Layer& l, int k) {
  std::vector<int> own;
  for (int c : l.cells)
    if (owner[size_t(c)] == k) own.push_back(c);
  return own;
}

}  // namespace

int HeightGrid::cell_of(const Vec2& p) const {
  const int i = int(std::floor((p.x() - origin.x()) / cell)), j = int(std::floor((p.y() - origin.y()) / cell));
  return i < 0 || j < 0 || i >= nx || j >= ny ? -1 : j * nx + i;
}

HeightGrid height_grid(const Polygon2& footprint, const std::vector<Vec3>& points, double cell) {
  HeightGrid g;
  g.cell = cell;
  Vec2 lo(1e300, 1e300), hi(-1e300, -1e300);
  for (const auto& v : footprint.outer) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
  if (footprint.outer.size() < 3) return g;
  g.origin = lo;
  g.nx = std::max(1, int(std::ceil((hi.x() - lo.x()) / cell)));
  g.ny = std::max(1, int(std::ceil((hi.y() - lo.y()) / cell)));
  const size_t n = size_t(g.nx) * size_t(g.ny);
  g.z.assign(n, kNaN);
  g.points.assign(n, 0);
  std::vector<bool> known(n, false);
  for (int i = 0; i < int(n); ++i)
    if (in_polygon_plan(footprint, g.centre(i))) g.z[size_t(i)] = -1e300;
  for (const auto& p : points) {
    const int c = g.cell_of(p.head<2>());
    if (c < 0 || !g.on_footprint(c)) continue;
    g.z[size_t(c)] = std::max(g.z[size_t(c)], p.z());
    ++g.points[size_t(c)];
    known[size_t(c)] = true;
  }
  fill_empty(g, known);
  return g;
}

std::vector<int> owner_of_cells(const HeightGrid& g, const std::vector<Layer>& layers) {
  std::vector<int> owner(g.z.size(), -1);
  for (size_t k = 0; k < layers.size(); ++k)  // parents come first: children overwrite them
    for (int c : layers[k].cells) owner[size_t(c)] = int(k);
  return owner;
}

std::vector<Layer> layer_tree(const HeightGrid& g, const LayerOptions& o) {
  std::vector<Layer> layers(1);
  for (int i = 0; i < g.nx * g.ny; ++i)
    if (g.on_footprint(i)) layers[0].cells.push_back(i);
  if (layers[0].cells.empty()) return {};
  std::vector<int> owner = owner_of_cells(g, layers);
  std::deque<int> todo{0};
  while (!todo.empty()) {
    const int k = todo.front();
    const Split s = int(layers.size()) < o.max_layers ? best_split(g, own_cells(owner, layers[size_t(k)], k), o)
                                                      : Split{};
    if (s.children.empty() || int(layers.size() + s.children.size()) > o.max_layers) {
      todo.pop_front();  // this layer is done; its own cells stay at its height
      continue;
    }
    for (const auto& p : s.children) {
      for (int c : p) owner[size_t(c)] = int(layers.size());
      layers.push_back({p, k, 0});
      todo.push_back(int(layers.size()) - 1);
    }
  }
  for (size_t k = 0; k < layers.size(); ++k) layers[k].z = median_height(g, own_cells(owner, layers[k], int(k)));
  return layers;
}

}  // namespace c3d::lod13

#include "core/reconstruct/ownership/point_grid.h"

#include <algorithm>
#include <cmath>

namespace c3d {
namespace {

// The cell holding coordinate v along one axis, clamped to [0, n).
long cell_of(double v, double origin, double cell, long n) {
  const double c = std::floor((v - origin) / cell);
  return c < 0 ? 0 : c >= double(n) ? n - 1 : long(c);
}

}  // namespace

PointGrid index_points(const std::vector<Vec3>& points, double cell) {
  PointGrid g;
  g.cell = cell;
  if (points.empty()) return g;
  Vec2 lo = points.front().head<2>(), hi = lo;
  for (const auto& p : points) lo = lo.cwiseMin(p.head<2>()), hi = hi.cwiseMax(p.head<2>());
  g.origin = lo;
  g.nx = long(std::floor((hi.x() - lo.x()) / cell)) + 1;
  g.ny = long(std::floor((hi.y() - lo.y()) / cell)) + 1;
  std::vector<long> cell_of_point(points.size());
  g.start.assign(size_t(g.nx * g.ny) + 1, 0);
  for (size_t i = 0; i < points.size(); ++i) {
    const long cx = cell_of(points[i].x(), g.origin.x(), cell, g.nx);
    const long cy = cell_of(points[i].y(), g.origin.y(), cell, g.ny);
    cell_of_point[i] = cy * g.nx + cx;
    ++g.start[size_t(cell_of_point[i]) + 1];
  }
  for (size_t c = 1; c < g.start.size(); ++c) g.start[c] += g.start[c - 1];
  g.index.resize(points.size());
  std::vector<int> next(g.start.begin(), g.start.end() - 1);
  for (size_t i = 0; i < points.size(); ++i) g.index[size_t(next[size_t(cell_of_point[i])]++)] = int(i);
  return g;
}

std::vector<int> points_in_box(const PointGrid& g, const Vec2& lo, const Vec2& hi) {
  std::vector<int> found;
  if (g.nx == 0 || hi.x() < lo.x() || hi.y() < lo.y()) return found;
  const long x0 = cell_of(lo.x(), g.origin.x(), g.cell, g.nx), x1 = cell_of(hi.x(), g.origin.x(), g.cell, g.nx);
  const long y0 = cell_of(lo.y(), g.origin.y(), g.cell, g.ny), y1 = cell_of(hi.y(), g.origin.y(), g.cell, g.ny);
  for (long cy = y0; cy <= y1; ++cy)
    for (long cx = x0; cx <= x1; ++cx) {
      const size_t c = size_t(cy * g.nx + cx);
      found.insert(found.end(), g.index.begin() + g.start[c], g.index.begin() + g.start[c + 1]);
    }
  std::sort(found.begin(), found.end());
  return found;
}

}  // namespace c3d

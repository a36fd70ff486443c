#include "core/geometry/hilbert.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace c3d {

// The classic iterative mapping: at each level, take the quadrant's digit and
// rotate/flip the rest so the sub-curve joins its neighbours.
std::uint64_t hilbert_index(std::uint32_t x, std::uint32_t y, int order) {
  std::uint64_t d = 0;
  for (std::uint32_t s = std::uint32_t(1) << (order - 1); s > 0; s >>= 1) {
    const std::uint32_t rx = (x & s) ? 1 : 0;
    const std::uint32_t ry = (y & s) ? 1 : 0;
    d += std::uint64_t(s) * s * ((3 * rx) ^ ry);
    if (ry == 0) {
      if (rx == 1) {
        x = s - 1 - (x & (s - 1)) + (x & ~(s - 1));
        y = s - 1 - (y & (s - 1)) + (y & ~(s - 1));
      }
      std::swap(x, y);
    }
  }
  return d;
}

std::vector<std::size_t> hilbert_order(const std::vector<Vec2>& points) {
  std::vector<std::size_t> order(points.size());
  std::iota(order.begin(), order.end(), 0);
  if (points.empty()) return order;
  Vec2 lo = points[0], hi = points[0];
  for (const Vec2& p : points) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  const double side = std::max({hi.x() - lo.x(), hi.y() - lo.y(), 1e-9});
  const double cells = double((std::uint64_t(1) << kHilbertOrder) - 1);
  std::vector<std::uint64_t> key(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const auto cell = [&](double v, double v0) { return std::uint32_t(std::lround((v - v0) / side * cells)); };
    key[i] = hilbert_index(cell(points[i].x(), lo.x()), cell(points[i].y(), lo.y()));
  }
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return key[a] < key[b]; });
  return order;
}

IndexRange part_range(std::size_t n, int k, int count) {
  const auto at = [&](int j) { return std::size_t((unsigned __int128)n * unsigned(j) / unsigned(count)); };
  return {at(k - 1), at(k)};
}

}  // namespace c3d

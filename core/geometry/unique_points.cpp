#include "core/geometry/unique_points.h"

#include <cmath>
#include <cstdint>
#include <unordered_map>

namespace c3d {
namespace {

struct Cell {
  std::int64_t x, y, z;
  bool operator==(const Cell& o) const { return x == o.x && y == o.y && z == o.z; }
};

struct CellHash {
  size_t operator()(const Cell& c) const {
    return size_t(c.x * 73856093LL) ^ size_t(c.y * 19349663LL) ^ size_t(c.z * 83492791LL);
  }
};

}  // namespace

UniquePoints unique_points(const std::vector<Vec3>& points, double tol) {
  UniquePoints u;
  u.of.assign(points.size(), -1);
  // Kept points by grid cell of side tol: a point within tol of a kept one
  // lies in that one's cell or a neighbouring cell.
  std::unordered_map<Cell, std::vector<int>, CellHash> grid;
  const double tol2 = tol * tol;
  auto cell_of = [&](const Vec3& p) {
    return Cell{std::int64_t(std::floor(p.x() / tol)), std::int64_t(std::floor(p.y() / tol)),
                std::int64_t(std::floor(p.z() / tol))};
  };
  for (size_t i = 0; i < points.size(); ++i) {
    const Cell c = cell_of(points[i]);
    int found = -1;
    for (std::int64_t dx = -1; dx <= 1 && found < 0; ++dx)
      for (std::int64_t dy = -1; dy <= 1 && found < 0; ++dy)
        for (std::int64_t dz = -1; dz <= 1 && found < 0; ++dz) {
          auto it = grid.find(Cell{c.x + dx, c.y + dy, c.z + dz});
          if (it == grid.end()) continue;
          for (int k : it->second)
            if ((points[size_t(u.unique[size_t(k)])] - points[i]).squaredNorm() <= tol2) {
              found = k;
              break;
            }
        }
    if (found < 0) {
      found = int(u.unique.size());
      u.unique.push_back(int(i));
      grid[c].push_back(found);
    }
    u.of[i] = found;
  }
  return u;
}

std::vector<Vec3> one_per_place(const std::vector<Vec3>& points) {
  const UniquePoints u = unique_points(points, kSamePlaceM);
  if (u.unique.size() == points.size()) return points;
  std::vector<Vec3> kept;
  kept.reserve(u.unique.size());
  for (int i : u.unique) kept.push_back(points[size_t(i)]);
  return kept;
}

}  // namespace c3d

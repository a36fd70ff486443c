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

namespace {

// one_per_place's grid: cells of twice the tolerance, so that a point's
// neighbours within tol lie in its own cell or the one beside it on each
// axis towards the nearer edge (8 cells, where unique_points looks in 27).
// A point this near a cell's middle looks both ways (rounding of p / side).
constexpr double kMiddleSlack = 1e-3;

struct MixHash {
  size_t operator()(const Cell& c) const {
    uint64_t h = uint64_t(c.x) * 0x9E3779B97F4A7C15ULL;
    h ^= uint64_t(c.y) * 0xC2B2AE3D27D4EB4FULL + (h << 6) + (h >> 2);
    h ^= uint64_t(c.z) * 0x165667B19E3779F9ULL + (h << 6) + (h >> 2);
    return size_t(h ^ (h >> 29));
  }
};

// Cell -> the last point kept in it, open addressing (no node per cell):
// a table at least twice the points, so probes stay short.
class CellTable {
 public:
  explicit CellTable(size_t points) {
    size_t n = 16;
    while (n < 2 * points) n *= 2;
    keys_.resize(n);
    heads_.assign(n, -1);
    mask_ = n - 1;
  }
  // The head slot of cell c; -1 when the cell holds no point yet.
  int& slot(const Cell& c, bool insert) {
    for (size_t at = MixHash()(c) & mask_;; at = (at + 1) & mask_) {
      if (heads_[at] < 0) {
        if (insert) keys_[at] = c;
        return insert ? heads_[at] : missing_ = -1;
      }
      if (keys_[at] == c) return heads_[at];
    }
  }

 private:
  std::vector<Cell> keys_;
  std::vector<int> heads_;
  size_t mask_ = 0;
  int missing_ = -1;
};

// The cells on one axis that may hold a point within tol of coordinate v.
int axis_cells(double v, double side, std::int64_t out[2]) {
  const double f = v / side, base = std::floor(f), frac = f - base;
  int n = 0;
  out[n++] = std::int64_t(base);
  if (frac < 0.5 + kMiddleSlack) out[n++] = std::int64_t(base) - 1;
  if (frac > 0.5 - kMiddleSlack) out[n++] = std::int64_t(base) + 1;
  return n;
}

}  // namespace

// The points unique_points keeps (each kept unless an earlier kept point lies
// within tol: the same set whatever cells are searched), found faster.
std::vector<Vec3> one_per_place(const std::vector<Vec3>& points) {
  const double tol = kSamePlaceM, tol2 = tol * tol, side = 2 * tol;
  CellTable head(points.size());
  std::vector<int> kept, before;  // kept points; per kept point, the one kept earlier in its cell
  kept.reserve(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    const Vec3& p = points[i];
    std::int64_t xs[3], ys[3], zs[3];
    const int nx = axis_cells(p.x(), side, xs), ny = axis_cells(p.y(), side, ys), nz = axis_cells(p.z(), side, zs);
    bool near = false;
    for (int a = 0; a < nx && !near; ++a)
      for (int b = 0; b < ny && !near; ++b)
        for (int c = 0; c < nz && !near; ++c)
          for (int k = head.slot(Cell{xs[a], ys[b], zs[c]}, false); k >= 0 && !near; k = before[size_t(k)])
            near = (points[size_t(kept[size_t(k)])] - p).squaredNorm() <= tol2;
    if (near) continue;
    int& h = head.slot(Cell{xs[0], ys[0], zs[0]}, true);
    before.push_back(h);
    h = int(kept.size());
    kept.push_back(int(i));
  }
  if (kept.size() == points.size()) return points;
  std::vector<Vec3> out;
  out.reserve(kept.size());
  for (int i : kept) out.push_back(points[size_t(i)]);
  return out;
}

}  // namespace c3d

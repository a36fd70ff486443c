#include "core/geometry/unique_points.h"

#include <algorithm>
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

// PlaceFolder's grid: cells of twice the tolerance, so that a point's
// neighbours within tol lie in its own cell or the one beside it on each
// axis towards the nearer edge (8 cells, where unique_points looks in 27).
// A point this near a cell's middle looks both ways (rounding of p / side).
constexpr double kMiddleSlack = 1e-3;
constexpr double kSide = 2 * kSamePlaceM;

size_t cell_hash(const Cell& c) {
  uint64_t h = uint64_t(c.x) * 0x9E3779B97F4A7C15ULL;
  h ^= uint64_t(c.y) * 0xC2B2AE3D27D4EB4FULL + (h << 6) + (h >> 2);
  h ^= uint64_t(c.z) * 0x165667B19E3779F9ULL + (h << 6) + (h >> 2);
  return size_t(h ^ (h >> 29));
}

Cell cell_of(const Vec3& p) {
  return {std::int64_t(std::floor(p.x() / kSide)), std::int64_t(std::floor(p.y() / kSide)),
          std::int64_t(std::floor(p.z() / kSide))};
}

// The cells on one axis that may hold a point within tol of coordinate v.
int axis_cells(double v, std::int64_t out[2]) {
  const double f = v / kSide, base = std::floor(f), frac = f - base;
  int n = 0;
  out[n++] = std::int64_t(base);
  if (frac < 0.5 + kMiddleSlack) out[n++] = std::int64_t(base) - 1;
  if (frac > 0.5 - kMiddleSlack) out[n++] = std::int64_t(base) + 1;
  return n;
}

}  // namespace

// A kept point is found from the cells p's neighbours may lie in: each
// cell's probe run (open addressing, linear) holds every kept point of that
// cell, among others; a point near p counts only where its own cell is the
// one searched, so exactly the kept points of the searched cells are asked.
bool PlaceFolder::near_kept(const Vec3& p) const {
  if (slots_.empty()) return false;
  const double tol2 = kSamePlaceM * kSamePlaceM;
  const size_t mask = slots_.size() - 1;
  std::int64_t xs[3], ys[3], zs[3];
  const int nx = axis_cells(p.x(), xs), ny = axis_cells(p.y(), ys), nz = axis_cells(p.z(), zs);
  for (int a = 0; a < nx; ++a)
    for (int b = 0; b < ny; ++b)
      for (int c = 0; c < nz; ++c) {
        const Cell cell{xs[a], ys[b], zs[c]};
        for (size_t s = cell_hash(cell) & mask; slots_[s] >= 0; s = (s + 1) & mask) {
          const Vec3& q = at(size_t(slots_[s]));
          if ((q - p).squaredNorm() <= tol2 && cell_of(q) == cell) return true;
        }
      }
  return false;
}

void PlaceFolder::insert(int i) {
  const size_t mask = slots_.size() - 1;
  size_t s = cell_hash(cell_of(at(size_t(i)))) & mask;
  while (slots_[s] >= 0) s = (s + 1) & mask;
  slots_[s] = i;
}

// Twice the slots at half load, so probe runs stay short.
void PlaceFolder::grow() {
  slots_.assign(std::max<size_t>(64, 2 * slots_.size()), -1);
  for (size_t i = 0; i < size_; ++i) insert(int(i));
}

void PlaceFolder::add(const Vec3& p) {
  if (near_kept(p)) return;
  if (2 * (size_ + 1) > slots_.size()) grow();
  if ((size_ & (kBlock - 1)) == 0) blocks_.emplace_back();
  blocks_.back().push_back(p);
  insert(int(size_++));
}

std::vector<Vec3> PlaceFolder::take() {
  std::vector<int>().swap(slots_);
  std::vector<Vec3> out;
  out.reserve(size_);
  for (auto& b : blocks_) {
    out.insert(out.end(), b.begin(), b.end());
    std::vector<Vec3>().swap(b);  // freed as copied: the points are held once, plus a block
  }
  blocks_.clear();
  size_ = 0;
  return out;
}

// The points unique_points keeps (each kept unless an earlier kept point lies
// within tol: the same set whatever cells are searched), found faster.
std::vector<Vec3> one_per_place(const std::vector<Vec3>& points) {
  PlaceFolder f;
  for (const Vec3& p : points) f.add(p);
  if (f.size() == points.size()) return points;
  return f.take();
}

}  // namespace c3d

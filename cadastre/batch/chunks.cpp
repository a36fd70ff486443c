#include "cadastre/batch/chunks.h"

#include <algorithm>
#include <cmath>

#include "core/geometry/hilbert.h"

namespace c3d {

std::vector<size_t> hilbert_sorted(const ParcelBoxes& boxes, const std::vector<size_t>& parcels) {
  std::vector<Vec2> places;
  for (size_t i = 0; i < boxes.size(); ++i) {
    const Box& b = boxes[i];
    places.emplace_back(b.empty() ? Vec2(0, 0) : Vec2((b.min_x + b.max_x) / 2, (b.min_y + b.max_y) / 2));
  }
  std::vector<char> wanted(boxes.size(), 0);
  for (size_t i : parcels) wanted[i] = 1;
  std::vector<size_t> out;
  for (size_t i : hilbert_order(places))
    if (wanted[i]) out.push_back(i);
  return out;
}

namespace {

// Tiles are seldom under 100 m: a parcel's box meets one cell or a few.
constexpr double kTileCellM = 128;

std::vector<Box> tile_extents(const std::vector<Tile>& tiles) {
  std::vector<Box> out;
  for (const Tile& t : tiles) out.push_back(t.extent);
  return out;
}

}  // namespace

RegionPointsEstimate::RegionPointsEstimate(const std::vector<Tile>& tiles)
    : extents_(tile_extents(tiles), kTileCellM) {
  for (const Tile& t : tiles) {
    const Box& e = t.extent;
    const double area = e.empty() ? 1.0 : std::max(1.0, (e.max_x - e.min_x) * (e.max_y - e.min_y));
    density_.push_back(double(t.points) / area);
  }
}

void RegionPointsEstimate::clear() {
  cells_.clear();
  total_ = 0;
}

double RegionPointsEstimate::add(const Box& part) {
  if (part.empty()) return total_;
  const std::vector<size_t> over = extents_.touching(part, 0);  // the tiles under the part
  const double c = kRegionCellM;
  const long x0 = long(std::floor(part.min_x / c)), x1 = long(std::floor(part.max_x / c));
  const long y0 = long(std::floor(part.min_y / c)), y1 = long(std::floor(part.max_y / c));
  for (long x = x0; x <= x1; ++x)
    for (long y = y0; y <= y1; ++y) {
      if (!cells_.insert(uint64_t(uint32_t(x)) << 32 | uint32_t(y)).second) continue;
      const Box cell{x * c, y * c, (x + 1) * c, (y + 1) * c};
      for (size_t k : over)
        if (extents_[k].touches(cell)) {
          const Box& e = extents_[k];  // the share of the cell the tile covers
          const double w = std::min(e.max_x, cell.max_x) - std::max(e.min_x, cell.min_x);
          const double h = std::min(e.max_y, cell.max_y) - std::max(e.min_y, cell.min_y);
          total_ += density_[k] * std::max(0.0, w) * std::max(0.0, h);
        }
    }
  return total_;
}

std::vector<std::vector<size_t>> cut_runs(const ParcelBoxes& boxes, const std::vector<Tile>& tiles,
                                          const std::vector<size_t>& order, const ChunkLimits& limits) {
  RegionPointsEstimate expected(tiles);
  std::vector<std::vector<size_t>> runs;
  bool full = true;
  for (size_t i : order) {
    if (full) runs.emplace_back(), expected.clear();
    runs.back().push_back(i);
    const double points = expected.add(boxes[i].grown(limits.reach));
    full = runs.back().size() >= std::max<size_t>(1, limits.parcels) || (limits.points > 0 && points >= limits.points);
  }
  return runs;
}

std::vector<std::vector<size_t>> spatial_chunks(const ParcelBoxes& boxes, const std::vector<Tile>& tiles,
                                                const std::vector<size_t>& parcels, const ChunkLimits& limits) {
  return cut_runs(boxes, tiles, hilbert_sorted(boxes, parcels), limits);
}

Box chunk_box(const ParcelBoxes& boxes, const std::vector<size_t>& chunk, double reach) {
  Box b;
  for (size_t i : chunk) b.add(boxes[i]);
  return b.grown(reach);
}

Region chunk_region(const ParcelBoxes& boxes, const std::vector<size_t>& chunk, double reach) {
  std::vector<Box> parts;
  for (size_t i : chunk) parts.push_back(boxes[i].grown(reach));
  return region_of(parts);
}

}  // namespace c3d

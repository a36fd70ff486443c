#pragma once
// How many roof points an ownership cell (0.5 m) typically holds, by place.
// A scan's density changes between flights and campaigns, so the figure is
// taken per block of kDensityBlockM on the working CRS's grid: the median
// count over the block's cells that hold roof points. Ownership asks for it
// per cell, so two parcels judge a cell they share alike whatever shard or
// chunk models them, and a run reads only the blocks its parcels lie in.
#include <map>
#include <utility>

namespace c3d {

// A town quarter: thousands of roof cells for a steady median, and within
// one flight's density.
constexpr double kDensityBlockM = 1000;

using CellIndex = std::pair<long, long>;  // a cell or block of a plan grid (column, row)

// The density block holding a roof cell (both in world indices).
CellIndex density_block(const CellIndex& world_cell);

struct RoofDensity {
  CellIndex offset{0, 0};           // the world roof cell of a scene's local cell (0, 0)
  std::map<CellIndex, int> typical;  // density block -> typical roof points per cell
  // The typical count of the block holding a local roof cell; 0 when unknown.
  int at(const CellIndex& local_cell) const;
};

}  // namespace c3d

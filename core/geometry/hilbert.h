#pragma once
// Spatial order along a Hilbert curve: places close on the curve are close on
// the ground, so a contiguous run of the order is a compact area. The batch
// cuts its parcels into shards and chunks by this order, so a shard or a chunk
// needs the points of one compact area, not of stripes across the town.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/types.h"

namespace c3d {

// Cells per side of the grid the curve visits: 2^16, finer than any parcel
// of a national layer (a 1,000 km extent gives 15 m cells).
constexpr int kHilbertOrder = 16;

// Position of cell (x, y) along the Hilbert curve over a 2^order grid.
std::uint64_t hilbert_index(std::uint32_t x, std::uint32_t y, int order = kHilbertOrder);

// Indices of `points` in Hilbert order over their bounding box; ties keep
// input order, so the same points give the same order.
std::vector<std::size_t> hilbert_order(const std::vector<Vec2>& points);

// The positions [begin, end) of part k (1-based) of `count` equal parts of n
// items: sizes differ by at most one, and the parts cover 0..n once.
struct IndexRange {
  std::size_t begin = 0, end = 0;
};
IndexRange part_range(std::size_t n, int k, int count);

}  // namespace c3d

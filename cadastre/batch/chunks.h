#pragma once
// The batch's spatial chunks: parcels in Hilbert order over the whole layer
// (core/geometry/hilbert.h; a parcel's place is the centre of its bounding
// box, the order shards cut too), cut into runs of a few hundred parcels or a few
// million points, so that a chunk's parcels lie together and its points are
// one compact region.
#include <cstddef>
#include <cstdint>
#include <unordered_set>
#include <vector>

#include "cadastre/batch/box_grid.h"
#include "cadastre/batch/parcel_boxes.h"
#include "cadastre/batch/tiles.h"
#include "core/types.h"

namespace c3d {

// `parcels` (layer indices) in the layer's Hilbert order.
std::vector<size_t> hilbert_sorted(const ParcelBoxes& boxes, const std::vector<size_t>& parcels);

// How large a chunk grows: `parcels` at most, and it ends at the parcel that
// takes the points its region is expected to read past `points` (0: no such
// bound), the region being its parcels' boxes grown by `reach`.
struct ChunkLimits {
  size_t parcels = 1;
  double points = 0;
  double reach = 0;
};

// The points a run's region is expected to read, of every class: each
// kRegionCellM cell of its parts counted once, at the density of the tiles
// over it (a tile's header count spread evenly over its extent). A dense
// area gets more, smaller chunks; a chunk's points, not its parcel count,
// decide its memory.
class RegionPointsEstimate {
 public:
  explicit RegionPointsEstimate(const std::vector<Tile>& tiles);
  double add(const Box& part);  // the run's expected points, this part added
  void clear();

 private:
  BoxGrid extents_;               // the tiles' extents
  std::vector<double> density_;  // points per m2, by tile
  std::unordered_set<uint64_t> cells_;
  double total_ = 0;
};

// `order` (parcels in the order chunks follow) cut into runs within `limits`.
std::vector<std::vector<size_t>> cut_runs(const ParcelBoxes& boxes, const std::vector<Tile>& tiles,
                                          const std::vector<size_t>& order, const ChunkLimits& limits);

// `parcels` in the layer's Hilbert order, cut into runs within `limits`.
std::vector<std::vector<size_t>> spatial_chunks(const ParcelBoxes& boxes, const std::vector<Tile>& tiles,
                                                const std::vector<size_t>& parcels, const ChunkLimits& limits);

// The box of the chunk's parcels grown by `reach`.
Box chunk_box(const ParcelBoxes& boxes, const std::vector<size_t>& chunk, double reach);
// Its region: the cells within that box near a parcel's box grown by `reach`.
// (The parcels a point in the box can lie within `reach` of, which a chunk's
// clippers hold: boxes.touching(box, reach).)
Region chunk_region(const ParcelBoxes& boxes, const std::vector<size_t>& chunk, double reach);

}  // namespace c3d

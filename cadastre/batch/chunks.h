#pragma once
// The batch's spatial chunks: parcels in Hilbert order over the whole layer
// (core/geometry/hilbert.h; a parcel's place is the centre of its bounding
// box, the order shards cut too), cut into runs of a few hundred, so that a
// chunk's parcels lie together and its points are one compact region.
#include <cstddef>
#include <vector>

#include "cadastre/batch/tiles.h"
#include "core/types.h"

namespace c3d {

// `parcels` (layer indices) in the layer's Hilbert order, cut into runs of
// `size` (at least 1).
std::vector<std::vector<size_t>> spatial_chunks(const ParcelLayer& layer, const std::vector<size_t>& parcels,
                                                size_t size);

// The box of the chunk's parcels grown by `reach`.
Box chunk_box(const ParcelLayer& layer, const std::vector<size_t>& chunk, double reach);
// The parcels whose boxes grown by `reach` touch the box: all that a point
// in the box can lie within `reach` of (a chunk's clippers hold these only).
std::vector<size_t> parcels_touching(const ParcelLayer& layer, const Box& box, double reach);
// Its region: the cells within that box near a parcel's box grown by `reach`.
Region chunk_region(const ParcelLayer& layer, const std::vector<size_t>& chunk, double reach);

}  // namespace c3d

#include "cadastre/batch/chunks.h"

#include <algorithm>

#include "core/geometry/hilbert.h"

namespace c3d {

std::vector<std::vector<size_t>> spatial_chunks(const ParcelLayer& layer, const std::vector<size_t>& parcels,
                                                size_t size) {
  std::vector<Vec2> places;
  for (const Parcel& p : layer.parcels) {
    const Box b = box_of(p.shape);
    places.emplace_back(b.empty() ? Vec2(0, 0) : Vec2((b.min_x + b.max_x) / 2, (b.min_y + b.max_y) / 2));
  }
  std::vector<char> wanted(layer.parcels.size(), 0);
  for (size_t i : parcels) wanted[i] = 1;
  std::vector<std::vector<size_t>> chunks;
  for (size_t i : hilbert_order(places)) {
    if (!wanted[i]) continue;
    if (chunks.empty() || chunks.back().size() >= std::max<size_t>(1, size)) chunks.emplace_back();
    chunks.back().push_back(i);
  }
  return chunks;
}

Box chunk_box(const ParcelLayer& layer, const std::vector<size_t>& chunk, double reach) {
  Box b;
  for (size_t i : chunk) b.add(box_of(layer.parcels[i].shape));
  return b.grown(reach);
}

std::vector<size_t> parcels_touching(const ParcelLayer& layer, const Box& box, double reach) {
  std::vector<size_t> out;
  for (size_t i = 0; i < layer.parcels.size(); ++i)
    if (box_of(layer.parcels[i].shape).grown(reach).touches(box)) out.push_back(i);
  return out;
}

Region chunk_region(const ParcelLayer& layer, const std::vector<size_t>& chunk, double reach) {
  std::vector<Box> parts;
  for (size_t i : chunk) parts.push_back(box_of(layer.parcels[i].shape).grown(reach));
  return region_of(parts);
}

}  // namespace c3d

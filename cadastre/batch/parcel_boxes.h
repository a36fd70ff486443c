#pragma once
// The layer's parcel boxes, computed once, with a grid over them: which
// parcels a chunk's region reaches, without a pass over the whole layer for
// every chunk (a million-parcel layer has thousands of chunks).
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "cadastre/batch/tiles.h"
#include "core/types.h"

namespace c3d {

class ParcelBoxes {
 public:
  ParcelBoxes() = default;
  explicit ParcelBoxes(const ParcelLayer& layer);
  size_t size() const { return boxes_.size(); }
  // Parcel i's bounding box in plan (empty for a parcel without a shape).
  const Box& operator[](size_t i) const { return boxes_[i]; }
  // The parcels whose boxes grown by `reach` touch `box`, ascending.
  std::vector<size_t> touching(const Box& box, double reach) const;

 private:
  std::vector<Box> boxes_;
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> grid_;  // cell -> parcels whose box meets it
};

}  // namespace c3d

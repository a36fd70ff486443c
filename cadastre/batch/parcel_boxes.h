#pragma once
// The layer's parcel boxes, computed once, with a grid over them: which
// parcels a chunk's region reaches, without a pass over the whole layer for
// every chunk (a million-parcel layer has thousands of chunks).
#include "cadastre/batch/box_grid.h"
#include "core/types.h"

namespace c3d {

// Parcel i's bounding box in plan is boxes[i] (empty for a parcel without a
// shape); touching(box, reach) gives the parcels near a box, ascending.
class ParcelBoxes : public BoxGrid {
 public:
  ParcelBoxes() = default;
  explicit ParcelBoxes(const ParcelLayer& layer);
};

}  // namespace c3d

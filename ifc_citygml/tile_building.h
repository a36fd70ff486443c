#pragma once
// A building as the 3D Tiles writer keeps it (tile_content.h): from the
// store's model and valuation, as its LoD 1.2 stand-in for the parent tiles,
// and as bytes in a cell's spool.
#include <cstdint>
#include <vector>

#include "core/types.h"
#include "ifc_citygml/tile_content.h"

namespace c3d {
struct ParcelValuation;
}

namespace c3d::tiles {

// Building b of result r, its faces triangulated in world coordinates (frame
// f); v is the parcel's valuation or null.
TileBuilding tile_building(const Building& b, const ParcelResult& r, const ParcelValuation* v, const LocalFrame& f);
// Its stand-in far off: the LoD 1.2 prism's faces, one element per type,
// each carrying the building's totals of that type from `full` (area, σ,
// amount), so a pick there reads the store's figures; `full` itself where
// the building has no prism.
TileBuilding coarse_building(const Building& b, const TileBuilding& full, const LocalFrame& f);

std::vector<std::uint8_t> to_bytes(const TileBuilding& b);
TileBuilding from_bytes(const std::vector<std::uint8_t>& bytes);

}  // namespace c3d::tiles

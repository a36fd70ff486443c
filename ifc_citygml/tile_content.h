#pragma once
// One 3D Tiles 1.1 content tile: the buildings of one cell as a binary glTF
// (docs/exports.md, "3D Tiles"). Every face of every element is its own
// triangles with the face's normal (flat shading) and the element type's
// colour; EXT_mesh_features numbers the vertices by building
// (_FEATURE_ID_0) and by element (_FEATURE_ID_1), and EXT_structural_metadata
// holds one property table of the buildings and one of the elements, so a
// viewer that picks a triangle reads the store's areas, σ and value.
// Written from the public specifications (Khronos glTF 2.0; OGC 3D Tiles 1.1;
// the Cesium EXT_mesh_features and EXT_structural_metadata extensions).
#include <array>
#include <string>
#include <vector>

#include "core/types.h"

namespace c3d::tiles {

// One element as the tile holds it: its faces' triangles in world
// coordinates (3 vertices a triangle, each face's triangles in a row).
struct TileElement {
  ElementType type = ElementType::Roof;
  double area = 0, sigma_area = 0, plan_area = 0, slope_deg = 0, rmse = 0;
  int support_points = 0;
  double amount = -1;  // its cost item's amount; -1 where unvalued
  std::vector<std::vector<Vec3>> faces;  // per face: triangle vertices, world
};

// A building with what a viewer shows when it is picked. Values are -1 where
// the parcel was not valued.
struct TileBuilding {
  std::string building_id, parcel_id, status, lod, currency;
  std::array<double, 6> areas{};  // roof, wall, party wall, ground, outer ceiling (m2), volume (m3)
  double building_value = -1, njop = -1, njop_per_m2 = -1, tax = -1;
  double height = 0, relief = 0;  // ridge above terrain; ridge above eaves (m)
  std::vector<TileElement> elements;
};

// The element type's colour (linear RGB, 0..1), the report's legend's.
std::array<float, 3> element_colour(ElementType t);

// The tile's bytes: vertices relative to `centre` (world), z up, turned onto
// glTF's y up by the node, which 3D Tiles turns back.
std::vector<unsigned char> tile_glb(const std::vector<TileBuilding>& buildings, const Vec3& centre);

}  // namespace c3d::tiles

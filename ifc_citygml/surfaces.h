#pragma once
// A building's surfaces at its primary LoD, each stored once (docs/exports.md):
// the closed solid's faces, each with the element it lies on, and the parts of
// element faces outside the solid (roof overhangs, hanging roofs, outer
// ceilings). The solid's faces and the outside pieces together cover every
// element face exactly once, so a sum over them by type equals the store's
// element totals.
#include <vector>

#include "core/types.h"

namespace c3d::exp {

struct SurfacePiece {
  Face face;
  ElementType type = ElementType::Wall;
  int element = -1;     // index in Building::elements; -1: a solid face on no element
  int solid_face = -1;  // index in Building::solid; -1: a piece outside the solid
};

struct BuildingSurfaces {
  std::vector<SurfacePiece> solid;    // one per Building::solid face, same order
  std::vector<SurfacePiece> outside;  // element parts that are not in the solid
};

BuildingSurfaces building_surfaces(const Building& b);

}  // namespace c3d::exp

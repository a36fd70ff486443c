#pragma once
// The LoD 1.3 solid: stacked prisms as one closed shell. The layers' outlines
// are noded into one planar subdivision; each piece takes the height of the
// highest layer over it and gets a flat top (a lower layer's top has holes or
// notches where a higher one stands on it); a wall stands on every edge
// between two pieces of different heights (a step wall) and on every edge of
// the footprint (down to the terrain); one ground face closes it. Every wall
// carries, on its vertical sides, each height at which another face meets
// that corner, so no edge of the shell ends in the middle of another.
#include <string>
#include <vector>

#include "core/types.h"

namespace c3d::lod13 {

struct LayerPiece {
  Polygon2 outline;  // inside the outline of the layer it stands on
  double z = 0;      // its top
};

struct StackedSolid {
  std::vector<Face> roofs;     // facing up
  std::vector<int> roof_layer; // per roof face, the layer it tops
  struct Wall {
    Face face;                 // facing out of the solid
    bool outer = false;        // on the footprint's boundary (else a step between layers)
    bool party = false;        // on a party edge of the footprint
  };
  std::vector<Wall> walls;
  Face ground;                 // facing down
  std::string problem;         // why no shell could be made ("" when it could)
};

// The shell of `layers` (layer 0 the footprint, parents before children; each
// later layer drawn over the earlier ones) standing on the terrain at
// terrain_z; party_edge per outer edge of layers[0].outline.
StackedSolid stacked_solid(const std::vector<LayerPiece>& layers, double terrain_z,
                           const std::vector<bool>& party_edge);

// Every face of the shell: ground, walls, roofs.
std::vector<Face> shell_of(const StackedSolid& s);

}  // namespace c3d::lod13

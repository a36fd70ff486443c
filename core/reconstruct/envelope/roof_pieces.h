#pragma once
// Envelope sub-stage "roof pieces": the roof regions cut by the footprint
// into pieces inside the walls (the solid's top) and hanging pieces (over
// the outer ceiling), in plan, all from one planar subdivision.
#include <vector>

#include "core/reconstruct/roof/roof.h"
#include "core/types.h"

namespace c3d::envelope {

struct Piece {
  int region = 0;
  bool inside = true;   // inside the walls (part of the solid) or hanging
  Polygon2 plan;
};

// The roof regions cut by the footprint `fp` into pieces, inside and
// hanging; slivers, thin spikes, gaps and stray fragments go to the
// neighbour they share most boundary with, so the pieces tile the regions.
std::vector<Piece> roof_pieces(const std::vector<RoofRegion>& roof, const Polygon2& fp);

// The pieces noded against each other and the footprint (a vertex of one on
// another's edge goes into that edge), each split where its ring passes
// twice through one vertex (an overhang frame's hole touching its outline).
std::vector<Piece> simple_pieces(std::vector<Piece> pieces, const Polygon2& fp);

}  // namespace c3d::envelope

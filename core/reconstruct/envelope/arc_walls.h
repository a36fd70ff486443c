#pragma once
// Envelope sub-stage "arc walls": the wall under an outline arc
// (outline/arcs.h) is one curved wall, not one per chord. Its chords take one
// overhang, grow onto a wall seen outside as one, and make one wall element
// (wall_faces.cpp).
#include <vector>

#include "core/reconstruct/envelope/envelope.h"
#include "core/reconstruct/envelope/wall_evidence.h"

namespace c3d::envelope {

// The chords of each arc (OutlineEdge::arc) take one overhang, the
// support-weighted median of those whose wall was seen; their position errs
// for all of them together (the arc's radius): shared, not each chord's own.
// `vertex_tolerance`: that of the grown outline, part of a measured wall's error.
void pool_arcs(std::vector<OutlineEdge>& edges, double vertex_tolerance);

// The walls found outside each arc's chords (`fits`, per edge of `ring`; `arc`
// per edge as arcs_in_ring gives) as one: each chord takes the
// support-weighted median offset of those found, so that the arc grows as one
// (concentric) or not at all.
void pool_arc_fits(const Ring2& ring, const std::vector<int>& arc, std::vector<WallFit>& fits);

}  // namespace c3d::envelope

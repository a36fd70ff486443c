#pragma once
// Envelope sub-stage "footprint": where the walls stand. Each outline edge
// moved inward by its overhang, corners where the moved lines meet, a step
// where two edges in one line overhang differently; a footprint that comes
// apart under the roof is reported (FootprintApart) and its largest part kept.
#include <functional>
#include <vector>

#include "core/reconstruct/envelope/envelope.h"
#include "core/reconstruct/envelope/wall_evidence.h"

namespace c3d::envelope {

// The footprint under `outline` from its edges' overhangs, within the outline;
// `apart` (if given) receives every part of at least kMinFootprintPart when
// the footprint comes apart. Throws where the outline holds no footprint.
Polygon2 footprint_from_edges(const std::vector<OutlineEdge>& edges, const Polygon2& outline,
                              double default_overhang, FootprintApart* apart);

// The footprint without edges shorter than 5 mm (of each such edge the end
// whose removal moves it least goes); fp itself where that leaves no valid polygon.
Polygon2 without_specks(const Polygon2& fp);

// Mean terrain height over the footprint (a 0.5 m grid and its corners).
// Throws where the terrain covers none of it.
double mean_terrain(const Polygon2& fp, const std::function<double(double, double)>& terrain);

// Whether the ring passes twice through one vertex (within the weld tolerance).
bool pinched(const Ring2& r);

// Whether the ring comes back to a vertex after leaving it (a pinch) or a
// vertex lies on an edge away from its ends (a fold), within the weld tolerance.
bool touches_itself(const Ring2& r);

// A ring passing twice through one vertex becomes two simple rings; holes go
// to the part holding them. Vertices closer than `tolerance` count as one.
std::vector<Polygon2> split_pinched(const Polygon2& p, double tolerance);

// Parts whose ring touches itself split into simple parts there.
MultiPolygon2 separate_pinched(const MultiPolygon2& parts);

}  // namespace c3d::envelope

#pragma once
// Envelope sub-stage "wall faces": the walls along the footprint from the
// terrain up to the roof underside (walls and party walls, one element per
// outline edge they stand under), and the step walls where two roof pieces
// inside the walls meet at different heights. wall_under, in envelope.h, is
// one such wall.
#include <map>
#include <vector>

#include "core/reconstruct/envelope/area_sigma.h"
#include "core/reconstruct/envelope/wall_evidence.h"
#include "core/types.h"

namespace c3d::envelope {

// A roof piece's edge over a footprint edge: from t0 to t1 along it, at
// heights z0 and z1, its ends at0 and at1 in plan (within the weld tolerance
// of the edge, not always on it); `along`: the piece's edge runs along the
// footprint edge, not across its end (a few millimetres of the next edge).
struct ProfileSegment {
  double t0, z0, t1, z1;
  Vec2 at0, at1;
  bool along;
};

// The roof underside along footprint edge a -> b, from the inside pieces'
// edges on it, latest start first.
std::vector<ProfileSegment> roof_profile(const Vec2& a, const Vec2& b,
                                         const std::vector<Face>& inside_faces);

// The wall under a -> b from ground_z up to the highest profile segment over
// each stretch of the edge.
Face wall_face(const Vec2& a, const Vec2& b, double ground_z,
               const std::vector<ProfileSegment>& profile);

// Vertical faces where two inside roof pieces meet at different heights,
// grouped by the roof region above them (region_of: per inside piece).
std::map<int, std::vector<Face>> step_walls(const std::vector<Face>& inside,
                                            const std::vector<int>& region_of);

// Footprint edge a -> b -> the outline edge it came from (parallel and nearest).
const OutlineEdge& source_edge(const std::vector<OutlineEdge>& edges, const Vec2& a, const Vec2& b);

// The walls along the footprint: their faces in footprint order (for the
// shell), one element per outline edge they stand under (its area's sigma
// from the walls' positions, area_sigma.h), and the sigma their positions give
// the ground area and the hanging roof's (the outer ceiling's) depth.
struct Facades {
  std::vector<Face> faces;
  std::vector<Element> elements;
  SharedSigma ground, eaves;  // m^2
};
Facades facade_walls(const Polygon2& fp, const std::vector<OutlineEdge>& edges, double ground_z,
                     const std::vector<Face>& inside, const RoofEdgeNoise& noise);

// The step walls between the inside pieces: their faces (for the shell) and
// one element per roof region above them.
struct StepWalls {
  std::vector<Face> faces;
  std::vector<Element> elements;
};
StepWalls step_wall_elements(const std::vector<Face>& inside, const std::vector<int>& inside_region);

// The step walls of at least 0.01 m^2 are appended to `elements`; smaller ones
// join the nearest wall element there (or are appended where there is none).
void fold_sliver_steps(std::vector<Element>& steps, std::vector<Element>& elements);

}  // namespace c3d::envelope

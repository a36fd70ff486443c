#pragma once
// Envelope sub-stage "wall evidence": the wall under each roof-outline edge,
// from the wall points (measured), from the building's other walls or the
// facade continuing on the neighbours (propagated), or the configured
// default overhang (default). fit_wall and grow_to_walls_outside, in
// envelope.h, are this sub-stage's public face.
#include <vector>

#include "core/reconstruct/envelope/envelope.h"

namespace c3d::envelope {

// Where no wall of the building is seen, an unseen wall's position is known
// only to the scatter of overhangs in general.
constexpr double kUnseenSpread = 0.3;  // m

// One roof-outline edge (outer[i] -> outer[i+1]) with the wall under it: the
// wall stands `overhang` inside the edge, known to within `sigma` (a measured
// or party wall: its position; one set back from the edge: its overhang, the
// edge's own error aside, area_sigma.h) and `sigma_shared` (an overhang the
// building's unseen walls all took: its error is theirs together).
struct OutlineEdge {
  Vec2 a, b;
  double overhang = 0;
  double sigma = 0;         // m
  double sigma_shared = kUnseenSpread;  // m
  int support = 0;
  double rms = 0;  // m, of the support points about the wall, in plan
  double outside = 0;  // m, how far outside the edge its wall was seen (it stands at the edge)
  bool party = false;
  WallEvidence evidence = WallEvidence::Default;
  int arc = -1;  // the outline arc this edge is a chord of (outline/arcs.h); -1: a straight edge
};

// Every outline edge of `in` with its wall: measured, propagated or default;
// party edges (on the parcel boundary) have no overhang.
std::vector<OutlineEdge> measure_edges(const EnvelopeInput& in);


// Median of values weighted by length: a building's overhang is what most of
// its eave length shows, not what most of its (often short) wall pieces show.
struct Weighted {
  double value, weight;
};
double weighted_median(std::vector<Weighted> v);

// The building's overhang from its seen walls: the length-weighted mean of
// those within kOverhangInlier (0.1 m) of the weighted median.
double typical_overhang(const std::vector<Weighted>& measured);

// A wall seen under outline edge `edge`, with its direction.
struct SeenWall {
  size_t edge;        // index into the outline's edges
  Vec2 dir;
  Weighted overhang;  // weighted by length
};
// The overhang of the facade parallel to `dir`, where the seen walls along it
// show one clearly apart from the building's; else `building`.
double facade_overhang(const std::vector<SeenWall>& seen, const Vec2& dir, double building);

// Whether a short edge's line runs on into the roof as a step between levels
// (an unseen wall under it is the step wall carried on: no overhang).
bool continues_step(const OutlineEdge& e, const std::vector<RoofRegion>& roof);

// The wall seen under edge e, from just above the terrain up to the roof over
// it; beyond_ends as for fit_wall.
WallFit fit_edge_wall(const EnvelopeInput& in, const OutlineEdge& e, bool beyond_ends = false);

// A point on a wall: its offset from the edge (negative: inside), its height.
struct FacadePoint {
  double offset, z;
};
using FacadePoints = std::vector<FacadePoint>;

// The offsets from each of `edges` (negative: inside) of those `points`
// that lie on a wall under it: each point along its nearest edge's
// middle, lower than the eave just inside that edge by kBelowEave, above the
// terrain's clutter (an airborne scan's facade points).
std::vector<FacadePoints> facade_offsets(const EnvelopeInput& in, const std::vector<OutlineEdge>& edges,
                                         const std::vector<Vec3>& points);

// The wall a few facade points of one edge show: the fullest 0.3 m window of
// their offsets, its median; found=false where too few, or too small a share
// of them, show one.
WallFit sparse_wall(const FacadePoints& offsets);

// The wall the facade points of all edges show together (a building's overhang).
WallFit pooled_sparse_wall(const std::vector<FacadePoints>& offsets);

}  // namespace c3d::envelope

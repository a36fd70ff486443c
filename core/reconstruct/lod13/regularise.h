#pragma once
// LoD 1.3, second half: a layer's outline as line segments, made regular step
// by step (parallel walls, preferred corner angles on the building's axes,
// alignment with the layer below and within the layer, short jogs removed);
// a step is kept only while the outline's IoU with the layer's own cells stays
// above a calibrated level (docs/lod13.md).
#include <functional>
#include <string>
#include <vector>

#include "core/types.h"

namespace c3d::lod13 {

// The level a regularised outline's IoU must keep: no lower than kMinIou, and
// no more than kMaxIouLoss below the IoU of the outline as found (calibrated
// on noisy synthetic outlines and the AHN3 town's layers: docs/lod13.md).
constexpr double kMinIou = 0.7;
constexpr double kMaxIouLoss = 0.03;

// A line segment of an outline: from a to b (the ring's direction).
struct Segment {
  Vec2 a, b;
  Vec2 dir() const { return (b - a).normalized(); }
  double length() const { return (b - a).norm(); }
};

struct RegulariseInput {
  Polygon2 outline;                            // as found (outer ring only is regularised)
  std::function<double(const Polygon2&)> iou;  // similarity of a candidate to the layer's cells
  double axis = 0;                  // the building's main direction, radians
  std::vector<Segment> below;       // the outline of the layer it stands on (aligned to)
  double align_m = 0.5;             // lines nearer than this are put on one line
  double min_edge_m = 0.5;          // shorter jogs are removed
};

struct Regularised {
  Polygon2 outline;
  double iou_found = 0, iou = 0;  // as found, as kept
  std::vector<std::string> steps; // the steps kept, in order
};

Regularised regularise(const RegulariseInput& in);

// The segments of a ring (edge i from vertex i to i+1).
std::vector<Segment> segments_of(const Ring2& ring);

// The ring through consecutive lines (each segment's line): neighbours that
// are parallel merge where they are collinear, else a square connector joins
// them at the point they shared. Empty where no simple counter-clockwise ring results.
Ring2 ring_through(const std::vector<Segment>& lines);

}  // namespace c3d::lod13

#pragma once
// Stacked points (a writer that repeats records, overlapping strips merged
// twice, coordinates rounded onto a grid) as one: a neighbourhood of k points
// that are four copies of four places fixes no normal, and a nearest
// neighbour at 0 m is no point spacing.
#include <vector>

#include "core/types.h"

namespace c3d {

// Points closer than this are one place scanned (or written) twice: far below
// any airborne scanner's noise (2-3 cm), far above float rounding.
constexpr double kSamePlaceM = 0.005;

struct UniquePoints {
  std::vector<int> unique;  // the points kept, one per place, in input order
  std::vector<int> of;      // per input point: the index into `unique` of its place
};

// The points of `points` closer than `tol` to an earlier kept point fold into
// it (first come, first kept: the same input gives the same result).
UniquePoints unique_points(const std::vector<Vec3>& points, double tol);

// The kept points of unique_points(points, kSamePlaceM): one per place, in
// input order. The batch measures and models these, and `evaluate` measures
// these, so that both count the same points.
std::vector<Vec3> one_per_place(const std::vector<Vec3>& points);

}  // namespace c3d

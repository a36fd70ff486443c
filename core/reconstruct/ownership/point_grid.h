#pragma once
// Points indexed once by plan cell, so that a question about the land along
// one outline edge reads the few cells around it instead of the whole scene.
#include <vector>

#include "core/types.h"

namespace c3d {

struct PointGrid {
  double cell = 1.0;        // m
  Vec2 origin = Vec2::Zero();  // the lower-left corner of cell (0, 0)
  long nx = 0, ny = 0;      // cells across and up; 0 with no points
  std::vector<int> start;   // per cell (row by row), where its points begin in `index`; one more at the end
  std::vector<int> index;   // the points' indices, cell by cell, ascending within each cell
};

// The grid of `points` (their plan positions) with square cells of `cell` metres.
PointGrid index_points(const std::vector<Vec3>& points, double cell);

// The indices, ascending, of the points in the cells the box [lo, hi] touches:
// every point inside the box and some beside it.
std::vector<int> points_in_box(const PointGrid& g, const Vec2& lo, const Vec2& hi);

}  // namespace c3d

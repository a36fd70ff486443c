#pragma once
// A grid of labels (one int per cell, -1 for none) and the polygons it makes:
// every connected run of equal cells becomes one polygon, edges on the cell
// lines. Done by GDAL's polygonize, which traces the cells' boundaries once
// instead of uniting thousands of cell boxes.
#include <vector>

#include "core/types.h"

namespace c3d {

struct LabelGrid {
  int nx = 0, ny = 0;
  Vec2 origin{0, 0};        // corner of cell (0, 0); row j spans y in [origin.y + j cell, + cell)
  double cell = 0.1;
  std::vector<int> labels;  // row-major, nx * ny; -1: no label
};

// Runs of equal cells (4-neighbours, as polygonize traces them) holding fewer
// than min_cells counted cells join the big neighbouring run they share the
// most cell edges with (edges with a counted cell on either side; ties to the
// lower label, so no float decides). A small run touching only small runs
// waits for a round in which one of them has joined a big run. Runs with no
// counted cell, and cells labelled -1, are left as they are.
void sieve(LabelGrid& grid, const std::vector<char>& counted, int min_cells);

// One MultiPolygon2 per label 0 .. label_count - 1 (empty where no cell has it).
std::vector<MultiPolygon2> polygonize(const LabelGrid& grid, size_t label_count);

}  // namespace c3d

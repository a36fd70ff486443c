#pragma once
// LoD 1.3, first half: a building's roof points as a tree of height layers.
// The points go into a plan grid over the footprint, each cell holding the
// highest point on it (a surface model: facade points under the eaves and
// stray low points hide under the roof); the footprint's cells are the root
// layer, and a layer is split while its own cells spread in height: the cells
// above the threshold that explains most of that spread form, per connected
// patch large enough for the point density, a layer standing on it. So every
// layer lies inside the one below it, and a lower part never leaves its parent.
#include <vector>

#include "core/types.h"

namespace c3d::lod13 {

// The surface model: cells of `cell` metres over the footprint's box.
struct HeightGrid {
  Vec2 origin = Vec2::Zero();  // the lower-left corner of cell (0, 0)
  double cell = 0.5;
  int nx = 0, ny = 0;
  std::vector<double> z;       // per cell: the highest point on it (filled where none); NaN off the footprint
  std::vector<int> points;     // per cell: how many roof points it holds

  bool on_footprint(int i) const { return z[size_t(i)] == z[size_t(i)]; }
  Vec2 centre(int i) const { return origin + cell * Vec2(i % nx + 0.5, i / nx + 0.5); }
  // The cell holding p, or -1 outside the grid.
  int cell_of(const Vec2& p) const;
};

// The grid over `footprint`: a cell is on it where its centre is; a cell on
// it without points takes the mean of its neighbours that have a height.
HeightGrid height_grid(const Polygon2& footprint, const std::vector<Vec3>& points, double cell);

struct LayerOptions {
  double min_area_m2 = 4;   // a layer's least area (the density's least point count included)
  double tolerance_m = 0.3; // a layer whose own cells spread less than this (rms) is not split
  double min_step_m = 0.5;  // a layer stands at least this far above the one it stands on
  int max_layers = 16;
};

struct Layer {
  std::vector<int> cells;  // its cells and those of every layer standing on it
  int parent = -1;         // the layer it stands on (-1: the root, on the terrain)
  double z = 0;            // its top: the median height of its own cells
};

// The layers, parents before their children; layer 0 is the footprint.
std::vector<Layer> layer_tree(const HeightGrid& g, const LayerOptions& o);

// Per cell, the index of the highest layer over it (-1 off the footprint).
std::vector<int> owner_of_cells(const HeightGrid& g, const std::vector<Layer>& layers);

}  // namespace c3d::lod13
